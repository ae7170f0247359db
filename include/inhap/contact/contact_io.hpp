// Writing contact points (detector.hpp) as a point PLY and as a CSV table.
// Units: positions mm, times s, forces N.
#pragma once

#include <span>
#include <string>

#include "inhap/contact/detector.hpp"
#include "inhap/geometry/trimesh.hpp"

namespace inhap {

/// Point cloud of the contacts (no faces): x,y,z = contact point; nx,ny,nz = unit force
/// direction at the tap's peak; vertex properties tap, t_contact, t_detect, peak_force,
/// estimated (1/0).
TriMesh contacts_to_points(std::span<const Contact> contacts);

/// Writes contacts_to_points() as PLY (binary little-endian unless `ascii`).
void write_contact_points(const std::string& path, std::span<const Contact> contacts,
                          bool ascii = false);

/// CSV with one row per tap: tap,t_detect,t_contact,x,y,z,dx,dy,dz,xd,yd,zd,peak_force,estimated
/// (x,y,z contact point; xd,yd,zd position at detection).
void write_contact_table(const std::string& path, std::span<const Contact> contacts);

}  // namespace inhap

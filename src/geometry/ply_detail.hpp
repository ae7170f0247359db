// Private to the PLY reader/writer: header model and type table. Units: none (file layout).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "inhap/geometry/ply.hpp"

namespace inhap::ply_detail {

enum class PlyType : std::uint8_t { kI8, kU8, kI16, kU16, kI32, kU32, kF32, kF64 };

/// Size in bytes of one binary value.
std::size_t type_size(PlyType t);
bool is_integer(PlyType t);
/// Canonical PLY name ("uchar", "float", ...).
const char* type_name(PlyType t);

struct PlyProperty {
  std::string name;
  bool is_list = false;
  PlyType type = PlyType::kF32;       ///< scalar type, or list item type
  PlyType count_type = PlyType::kU8;  ///< list count type (lists only)
  std::size_t line = 0;               ///< header line declaring it
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> props;
  std::size_t line = 0;
};

struct PlyHeader {
  PlyFormat format = PlyFormat::kAscii;
  std::vector<PlyElement> elements;
  std::size_t data_offset = 0;  ///< first byte after the end_header line
  std::size_t lines = 0;        ///< number of header lines (the end_header line included)
};

/// Parses and checks the header: magic, format, elements, properties, end_header, and that the
/// declared element counts fit in the bytes that follow (so no absurd allocation can happen).
/// Throws ParseError naming `source` and the header line.
PlyHeader parse_header(std::string_view bytes, const std::string& source);

}  // namespace inhap::ply_detail

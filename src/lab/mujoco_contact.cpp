// Virtual lab, MuJoCo backend: see mujoco_contact.hpp and docs/lab-mujoco.md.
// Units: mm, mm/s, N, s at the interface; MuJoCo runs in m, kg, s.
#include "mujoco_contact.hpp"

#include <fmt/format.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <string>
#include <type_traits>

#include "inhap/core/error.hpp"

#ifdef INHAP_HAVE_MUJOCO
#include <mujoco/mujoco.h>
#endif

namespace inhap::lab {

const char* to_string(Physics p) {
  return p == Physics::kMujoco ? "mujoco" : "builtin";
}

bool mujoco_represents(const Shape& shape) {
  return std::visit(
      [](const auto& g) {
        using T = std::decay_t<decltype(g)>;
        return std::is_same_v<T, CylinderShape> || std::is_same_v<T, DomeShape> ||
               std::is_same_v<T, HemisphereShape> || std::is_same_v<T, SphereShape> ||
               std::is_same_v<T, BoxShape>;
      },
      shape.variant());
}

Physics physics_from_string(const std::string& s) {
  if (s == "builtin") return Physics::kBuiltin;
  if (s == "mujoco") return Physics::kMujoco;
  throw Error(fmt::format("expected physics 'builtin' or 'mujoco', got '{}'", s));
}

#ifdef INHAP_HAVE_MUJOCO

bool mujoco_available() {
  return true;
}

namespace {

constexpr double kMm = 1e-3;  // mm -> m

std::atomic<int> g_warnings{0};
// MuJoCo's default warning handler prints and appends to MUJOCO_LOG.TXT: no I/O in a step.
void count_warning(const char*) {
  ++g_warnings;
}

// MuJoCo's impedance d(r) of solimp (d0, dmax, width, mid, power) at violation r >= 0 (m):
// the polynomial sigmoid of engine_core_constraint.c (getimpedance), MuJoCo 2.2.
double impedance(const MujocoParams& p, double r) {
  const double d0 = p.solimp_d0, d1 = p.solimp_dmax, w = p.solimp_width_mm * kMm;
  const double x = r / w;
  if (x >= 1) return d1;
  if (x <= 0) return d0;
  const double mid = p.solimp_mid, pw = p.solimp_power;
  double y = x;
  if (pw != 1) {
    if (x <= mid)
      y = std::pow(x, pw) / std::pow(mid, pw - 1);
    else
      y = 1 - std::pow(1 - x, pw) / std::pow(1 - mid, pw - 1);
  }
  return d0 + y * (d1 - d0);
}

std::string geom_xml(const Shape& shape, double shrink_mm) {
  const double s = shrink_mm;
  return std::visit(
      [s](const auto& g) -> std::string {
        using T = std::decay_t<decltype(g)>;
        auto v3 = [](const Vec3& v) {
          return fmt::format("{} {} {}", v.x() * kMm, v.y() * kMm, v.z() * kMm);
        };
        // Flat tops (cylinder, box) are MuJoCo planes (half-spaces) at the top face: MuJoCo's
        // sphere-box contact is lost once the sphere's centre enters the box (an 8 mm probe
        // fell through the soft planar top at 3 N, the tip through the silicone block at 1 N),
        // the plane-sphere contact is exact at any depth. The sides are not represented: the
        // lab's operators touch the top face (docs/lab-mujoco.md).
        if constexpr (std::is_same_v<T, CylinderShape>) {
          const Vec3 c = g.base_center + Vec3(0, 0, g.height - s);
          return fmt::format("type=\"plane\" pos=\"{}\" size=\"{} {} 0.01\"", v3(c), g.radius * kMm,
                             g.radius * kMm);
        } else if constexpr (std::is_same_v<T, DomeShape>) {  // the cap's sphere
          const double rs = (g.base_radius * g.base_radius + g.height * g.height) / (2 * g.height);
          const Vec3 c = g.base_center + Vec3(0, 0, g.height - rs);
          return fmt::format("type=\"sphere\" pos=\"{}\" size=\"{}\"", v3(c), (rs - s) * kMm);
        } else if constexpr (std::is_same_v<T, HemisphereShape>) {
          return fmt::format("type=\"sphere\" pos=\"{}\" size=\"{}\"", v3(g.base_center),
                             (g.radius - s) * kMm);
        } else if constexpr (std::is_same_v<T, SphereShape>) {
          return fmt::format("type=\"sphere\" pos=\"{}\" size=\"{}\"", v3(g.center),
                             (g.radius - s) * kMm);
        } else if constexpr (std::is_same_v<T, BoxShape>) {
          const Vec3 c = g.center + Vec3(0, 0, g.half_size.z() - s);
          return fmt::format("type=\"plane\" pos=\"{}\" size=\"{} {} 0.01\"", v3(c),
                             g.half_size.x() * kMm, g.half_size.y() * kMm);
        } else {
          return {};
        }
      },
      shape.variant());
}

struct ModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct DataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};

mjModel* load_from_string(const std::string& xml) {
  auto vfs = std::make_unique<mjVFS>();
  mj_defaultVFS(vfs.get());
  const char* name = "inhap_probe.xml";
  if (mj_makeEmptyFileVFS(vfs.get(), name, static_cast<int>(xml.size())) != 0)
    throw Error("MuJoCo: could not allocate the in-memory model file");
  const int i = mj_findFileVFS(vfs.get(), name);
  std::memcpy(vfs->filedata[i], xml.data(), xml.size());
  char err[1000] = "";
  mjModel* m = mj_loadXML(name, vfs.get(), err, sizeof(err));
  mj_deleteVFS(vfs.get());
  if (!m) throw Error(fmt::format("MuJoCo: could not load the lab model: {}", err));
  return m;
}

}  // namespace

struct MujocoContact::Impl {
  const SoftObject& object;
  double radius;  // probe radius as the lab sees it (0: sharp tip), mm
  double dt;
  MujocoParams prm;
  std::unique_ptr<mjModel, ModelDeleter> m;
  std::unique_ptr<mjData, DataDeleter> d;
  int geom_object = -1, geom_probe = -1, body_probe = -1;
  // Coupling force on the probe body for the coming step, N: the same force whose opposite the
  // device integrated over its last substep (action = reaction, see step()).
  Vec3 f_probe = Vec3::Zero();

  Impl(const SoftObject& obj, double r, double step, const MujocoParams& p)
      : object(obj), radius(r), dt(step), prm(p) {}

  Vec3 x() const { return Vec3(d->qpos[0], d->qpos[1], d->qpos[2]) / kMm; }
  Vec3 v() const { return Vec3(d->qvel[0], d->qvel[1], d->qvel[2]) / kMm; }
  double inv_mass() const { return m->body_invweight0[2 * body_probe]; }

  // solref (-k_s, -b_s) and friction of the material at x (mm), so that the static depth of
  // the device at 5 N (contact + normal coupling) is the scene's ContactLaw::depth_at(5).
  void set_material(const Vec3& at) {
    const ContactLaw law = object.law_at(at);
    const double r5 = std::max(0.05, law.depth_at(5.0) - 5.0 / prm.coupling_normal_n_per_mm);
    const double rm = r5 * kMm, imp = impedance(prm, rm), w = inv_mass();
    const double k = 5.0 * w * (1 - imp) / (imp * imp * rm);
    const double b = 2 * prm.contact_damping_ratio * std::sqrt(k * (1 - imp));
    const double dmax = prm.solimp_dmax;
    m->geom_solref[2 * geom_object] = -k * dmax * dmax;
    m->geom_solref[2 * geom_object + 1] = -b * dmax;
    m->geom_friction[3 * geom_object] = law.mu;
  }

  // Coupling force on the probe body, N: stiff along the normal, k_t across it.
  Vec3 coupling(const Vec3& p, const Vec3& pv, const Vec3& n, double k_t) const {
    const Vec3 e = p - x(), ev = pv - v();
    const Vec3 en = e.dot(n) * n, evn = ev.dot(n) * n;
    const double mass = 1.0 / inv_mass();
    const double kn = prm.coupling_normal_n_per_mm;
    // c = 2 zeta sqrt(k m), k in N/m -> c in N s/m; * 1e-3 -> N s/mm.
    const double cn = 2 * prm.coupling_damping_ratio * std::sqrt(kn * 1e3 * mass) * 1e-3;
    const double ct = 2 * prm.coupling_damping_ratio * std::sqrt(k_t * 1e3 * mass) * 1e-3;
    return kn * en + k_t * (e - en) + cn * evn + ct * (ev - evn);
  }

  bool touching() const {
    for (int i = 0; i < d->ncon; ++i) {
      const mjContact& c = d->contact[i];
      const bool pair = (c.geom1 == geom_object && c.geom2 == geom_probe) ||
                        (c.geom2 == geom_object && c.geom1 == geom_probe);
      if (pair && c.dist < 0 && c.efc_address >= 0) return true;
    }
    return false;
  }

  void update_truth(const Vec3& p, const Vec3& f_device, double t, ContactState& st) {
    const Vec3 xp = x();
    const SurfaceQuery s = object.query(xp);
    const double delta = radius - s.distance;
    if (touching()) {
      if (!st.in_contact) {
        double frac = 1.0;
        if (st.has_prev && st.prev_delta <= 0 && delta > st.prev_delta)
          frac = -st.prev_delta / (delta - st.prev_delta);
        st.start_point = st.has_prev ? Vec3(st.prev_point + frac * (p - st.prev_point)) : p;
        st.start_time = st.has_prev ? st.prev_time + frac * (t - st.prev_time) : t;
        st.in_contact = true;
        ++st.episode;
      }
      st.proxy = project_to_offset(object, radius, xp);
      st.law = object.law_at(st.proxy);
      st.normal = s.normal;
      st.delta = delta;
      st.normal_force = f_device.dot(s.normal);
      st.force = f_device;
      const Vec3 vt = v() - v().dot(s.normal) * s.normal;
      st.slipping = vt.norm() > 0.5;  // mm/s
    } else if (st.in_contact) {
      st.in_contact = st.slipping = false;
      st.delta = st.normal_force = 0;
      st.force.setZero();
    }
    st.has_prev = true;
    st.prev_delta = delta;
    st.prev_time = t;
    st.prev_point = p;
  }
};

MujocoContact::MujocoContact(const SoftObject& object, double probe_radius, double dt,
                             const MujocoParams& params)
    : impl_(std::make_unique<Impl>(object, probe_radius, dt, params)) {
  mju_user_warning = count_warning;
  const bool tip = !(probe_radius > 0);
  const double r_mj = tip ? params.tip_radius_mm : probe_radius;
  const std::string geom = geom_xml(object.shape(), tip ? r_mj : 0.0);
  if (geom.empty())
    throw Error(fmt::format(
        "MuJoCo lab: a {} shape cannot be represented (expected cylinder, dome, hemisphere, "
        "sphere or box)",
        object.shape().type_name()));
  const MujocoParams& p = params;
  const std::string xml = fmt::format(
      R"(<mujoco model="inhap-lab">
  <compiler angle="radian"/>
  <option timestep="{dt}" gravity="0 0 0" cone="elliptic" impratio="{impratio}" integrator="Euler" noslip_iterations="{noslip}"/>
  <worldbody>
    <geom name="object" {geom} priority="1" condim="3" friction="1 0 0"
          solref="-1000 -10" solimp="{d0} {d1} {w} {mid} {pw}"/>
    <body name="probe" pos="0 0 0">
      <joint name="px" type="slide" axis="1 0 0"/>
      <joint name="py" type="slide" axis="0 1 0"/>
      <joint name="pz" type="slide" axis="0 0 1"/>
      <geom name="probe" type="sphere" size="{r}" mass="{mass}" condim="3" friction="0 0 0"/>
    </body>
  </worldbody>
</mujoco>
)",
      fmt::arg("dt", dt), fmt::arg("impratio", p.impratio), fmt::arg("noslip", p.noslip_iterations),
      fmt::arg("geom", geom), fmt::arg("d0", p.solimp_d0), fmt::arg("d1", p.solimp_dmax),
      fmt::arg("w", p.solimp_width_mm * kMm), fmt::arg("mid", p.solimp_mid),
      fmt::arg("pw", p.solimp_power), fmt::arg("r", r_mj * kMm), fmt::arg("mass", p.probe_mass_kg));
  Impl& s = *impl_;
  s.m.reset(load_from_string(xml));
  s.d.reset(mj_makeData(s.m.get()));
  if (!s.d) throw Error("MuJoCo: could not allocate the lab model's data");
  s.geom_object = mj_name2id(s.m.get(), mjOBJ_GEOM, "object");
  s.geom_probe = mj_name2id(s.m.get(), mjOBJ_GEOM, "probe");
  s.body_probe = mj_name2id(s.m.get(), mjOBJ_BODY, "probe");
}

MujocoContact::~MujocoContact() = default;

void MujocoContact::place(const Vec3& p, ContactState& state, double t) {
  Impl& s = *impl_;
  for (int k = 0; k < 3; ++k) {
    s.d->qpos[k] = p[k] * kMm;
    s.d->qvel[k] = 0;
    s.d->qfrc_applied[k] = 0;
  }
  s.f_probe.setZero();
  s.set_material(p);
  mj_forward(s.m.get(), s.d.get());
  const auto episode = state.episode;
  state.reset();
  state.episode = episode;
  s.update_truth(p, Vec3::Zero(), t, state);
}

Vec3 MujocoContact::step(const Vec3& p, const Vec3& v, double t, ContactState& state) {
  Impl& s = *impl_;
  if (!all_finite(p) || !all_finite(v)) return Vec3::Zero();
  // The probe body feels the coupling force computed at the end of the previous step (device
  // and probe at the same instant), the force whose opposite the device has just integrated.
  // Evaluating it again with the device already moved and the probe not yet would stretch
  // the spring by v dt in the direction of motion on the probe's side only: a net force
  // k_n v dt on the pair (negative damping, the free device accelerated away at ~25/s).
  for (int k = 0; k < 3; ++k) s.d->qfrc_applied[k] = s.f_probe[k];
  s.set_material(s.x());
  mj_step(s.m.get(), s.d.get());
  const Vec3 x1 = s.x();
  const SurfaceQuery q1 = s.object.query(x1);
  s.f_probe = s.coupling(p, v, q1.normal, s.object.law_at(x1).k_t);
  const Vec3 f_device = -s.f_probe;
  s.update_truth(p, f_device, t, state);
  return f_device;
}

double MujocoContact::static_force(const Vec3& at, double r_mm) const {
  Impl& s = *impl_;
  s.set_material(at);
  const double rm = r_mm * kMm, imp = impedance(s.prm, rm);
  const double dmax = s.prm.solimp_dmax;
  const double k = -s.m->geom_solref[2 * s.geom_object] / (dmax * dmax);
  return k * imp * imp * rm / ((1 - imp) * s.inv_mass());
}

Vec3 MujocoContact::probe_position() const {
  return impl_->x();
}

int MujocoContact::warnings() const {
  return g_warnings.load();
}

#else  // no MuJoCo in this build

bool mujoco_available() {
  return false;
}

struct MujocoContact::Impl {};

MujocoContact::MujocoContact(const SoftObject&, double, double, const MujocoParams&) {
  throw Error("physics 'mujoco': this build has no MuJoCo (install libmujoco-dev and rebuild)");
}
MujocoContact::~MujocoContact() = default;
void MujocoContact::place(const Vec3&, ContactState&, double) {}
Vec3 MujocoContact::step(const Vec3&, const Vec3&, double, ContactState&) {
  return Vec3::Zero();
}
double MujocoContact::static_force(const Vec3&, double) const {
  return 0;
}
Vec3 MujocoContact::probe_position() const {
  return Vec3::Zero();
}
int MujocoContact::warnings() const {
  return 0;
}

#endif

}  // namespace inhap::lab

// inhap studio session: the sampling, explore and experiment views' commands (session.hpp).
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <limits>

#include "inhap/core/atomic_file.hpp"
#include "inhap/core/error.hpp"
#include "inhap/datadriven/model_io.hpp"
#include "inhap/geometry/mesh_io.hpp"
#include "inhap/geometry/obj.hpp"
#include "inhap/geometry/ply.hpp"
#include "inhap/studio/display.hpp"
#include "inhap/studio/session.hpp"
#include "inhap/surface/reconstruct.hpp"

namespace inhap::studio {
namespace {

// A PLY or OBJ read through the workspace guard; errors name the path as the page gave it.
TriMesh read_workspace_mesh(const Workspace& ws, const std::string& rel) {
  std::string ext = std::filesystem::path(rel).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext != ".ply" && ext != ".obj")
    throw ProtocolError(fmt::format("{}: expected a .ply or .obj file", quote_input(rel, 200)));
  const std::string bytes = ws.read(rel);
  return ext == ".ply" ? parse_ply(bytes, quote_input(rel, 200))
                       : parse_obj(bytes, quote_input(rel, 200));
}

}  // namespace

// --- sampling --------------------------------------------------------------------------------

void Session::on_contact(const Contact& c) {
  Sample s;
  s.point = c.point;
  s.threshold = c.p_detect;
  s.direction = c.direction;
  s.t_contact = c.t_contact;
  s.peak_force = c.peak_force;
  s.estimated = c.estimated;
  {
    std::lock_guard lock(data_mu_);
    s.id = next_id_++;
    samples_.push_back(s);
  }
  nlohmann::json j = sample_json(s);
  j["type"] = "tap";
  j["taps"] = s.id + 1;
  broadcast_(j.dump());
}

std::size_t Session::live_samples() const {
  std::lock_guard lock(data_mu_);
  return static_cast<std::size_t>(
      std::count_if(samples_.begin(), samples_.end(), [](const Sample& s) { return !s.deleted; }));
}

std::string Session::samples_json() const {
  nlohmann::json pts = nlohmann::json::array();
  std::size_t deleted = 0;
  long taps = 0;
  {
    std::lock_guard lock(data_mu_);
    taps = next_id_;
    for (const Sample& s : samples_) {
      if (s.deleted)
        ++deleted;
      else
        pts.push_back(sample_json(s));
    }
  }
  return nlohmann::json{{"type", "samples"},
                        {"samples", pts},
                        {"deleted", deleted},
                        {"undo", undo_.size()},
                        {"taps", taps}}
      .dump();
}

std::string Session::do_delete(const Message& m) {
  const auto ids = get_integer_list(m, "ids", 0, std::numeric_limits<int>::max(), 100000);
  {
    std::lock_guard lock(data_mu_);
    std::vector<Sample*> hit;  // every id checked before any sample changes
    for (long id : ids) {
      auto it = std::find_if(samples_.begin(), samples_.end(),
                             [id](const Sample& s) { return s.id == id && !s.deleted; });
      if (it == samples_.end()) throw ProtocolError(fmt::format("delete: no live sample {}", id));
      hit.push_back(&*it);
    }
    for (Sample* s : hit) s->deleted = true;
    undo_.push_back({ids, {}});
  }
  return samples_json();
}

std::string Session::do_undo() {
  {
    std::lock_guard lock(data_mu_);
    if (undo_.empty()) throw ProtocolError("undo: nothing to undo");
    for (long id : undo_.back().deleted)
      for (Sample& s : samples_)
        if (s.id == id) s.deleted = false;
    for (const auto& [id, point] : undo_.back().moved)
      for (Sample& s : samples_)
        if (s.id == id) s.point = point;
    undo_.pop_back();
  }
  return samples_json();
}

std::string Session::do_reconstruct(const Message& m) {
  ReconstructOptions o;
  o.alpha = get_number_or(m, "alpha", 0, 1000, 0);
  if (!get_bool_or(m, "taubin", true)) o.taubin_iterations = 0;
  if (!get_bool_or(m, "sqrt3", true)) o.subdivisions = 0;
  std::vector<Vec3> pts, dirs;
  {
    std::lock_guard lock(data_mu_);
    for (const Sample& s : samples_)
      if (!s.deleted) pts.push_back(s.point), dirs.push_back(s.direction);
  }
  if (pts.size() < 8)
    throw ProtocolError(fmt::format("reconstruct: {} samples, expected at least 8", pts.size()));
  ReconstructReport rep;
  const auto t0 = std::chrono::steady_clock::now();
  TriMesh mesh = reconstruct_surface(pts, dirs, o, &rep);
  fmt::print(stderr, "studio: reconstructed {} samples -> {} faces (alpha {:.2f} mm) in {:.1f} s\n",
             pts.size(), mesh.num_triangles(), rep.alpha,
             std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  std::vector<double> dist(mesh.num_vertices());
  for (std::size_t v = 0; v < dist.size(); ++v) {
    double best = std::numeric_limits<double>::infinity();
    for (const Vec3& p : pts) best = std::min(best, (mesh.positions[v] - p).squaredNorm());
    dist[v] = std::sqrt(best);
  }
  mesh.set_property("distance", dist);
  nlohmann::json j = nlohmann::json::parse(mesh_json(mesh, "reconstruction", "distance"));
  j["report"] = {{"points_in", rep.points_in}, {"outliers", rep.outliers},
                 {"alpha", rep.alpha},         {"faces", rep.faces},
                 {"vertices", rep.vertices},   {"components", rep.components}};
  std::vector<long> outlier_ids;
  {
    std::lock_guard lock(data_mu_);
    std::size_t k = 0;
    for (const Sample& s : samples_)
      if (!s.deleted) {
        if (k < rep.used.size() && !rep.used[k]) outlier_ids.push_back(s.id);
        ++k;
      }
    reconstruction_ = std::move(mesh);
  }
  j["outliers"] = outlier_ids;
  return j.dump();
}

std::string Session::do_export(const Message& m) {
  const std::string points_rel = get_string(m, "points");
  std::optional<std::string> mesh_rel;
  if (m.body.contains("mesh")) mesh_rel = get_string(m, "mesh");
  const WorkspacePath points_out = workspace_.output(points_rel);
  std::optional<WorkspacePath> mesh_out;
  if (mesh_rel) mesh_out.emplace(workspace_.output(*mesh_rel));
  const WorkspacePath* mesh_ptr = mesh_out ? &*mesh_out : nullptr;
  for (const WorkspacePath* p : {&points_out, mesh_ptr}) {
    if (!p) continue;
    const std::string ext = std::filesystem::path(p->path()).extension().string();
    if (ext != ".ply" && ext != ".obj")
      throw ProtocolError(fmt::format("export: {}: expected a .ply or .obj name", p->name()));
  }
  TriMesh cloud;
  {
    std::lock_guard lock(data_mu_);
    if (mesh_out && !reconstruction_) throw ProtocolError("export: no reconstruction yet");
    for (const Sample& s : samples_)
      if (!s.deleted) cloud.positions.push_back(s.point), cloud.normals.push_back(s.direction);
    if (cloud.positions.empty()) throw ProtocolError("export: no samples");
  }
  with_names({&points_out, mesh_ptr}, [&] {
    OutputTransaction tx;  // both files or neither
    write_mesh(points_out.path(), cloud);
    if (mesh_out) write_mesh(mesh_out->path(), *reconstruction_);
    tx.commit();
  });
  nlohmann::json j{{"type", "ok"}, {"request", "export"}, {"points", cloud.num_vertices()}};
  if (mesh_out) j["faces"] = reconstruction_->num_triangles();
  return j.dump();
}

std::string Session::do_save_session(const Message& m) {
  const std::string path = get_string(m, "path");
  nlohmann::json pts = nlohmann::json::array();
  {
    std::lock_guard lock(data_mu_);
    for (const Sample& s : samples_) {
      nlohmann::json j = sample_json(s);
      j["deleted"] = s.deleted;
      pts.push_back(j);
    }
  }
  nlohmann::json doc{{"format", "inhap-studio-session"},
                     {"version", 1},
                     {"units", "mm, N, s"},
                     {"device", options_.device},
                     {"operator", lab_ ? "tap (simulated)" : "device"},
                     {"seed", options_.seed},
                     {"samples", pts}};
  workspace_.write(path, dump_safe(doc) + "\n");
  return nlohmann::json{{"type", "ok"}, {"request", "save_session"}, {"samples", pts.size()}}
      .dump();
}

std::string Session::do_open_session(const Message& m) {
  const std::string path = get_string(m, "path");
  std::vector<Sample> loaded = parse_session_file(workspace_.read(path), path);
  long next = 0;
  for (const Sample& s : loaded) next = std::max(next, s.id + 1);
  {
    std::lock_guard lock(data_mu_);
    samples_ = std::move(loaded);
    next_id_ = std::max(next_id_, next);
    undo_.clear();
  }
  return samples_json();
}

// --- explore ---------------------------------------------------------------------------------

std::string Session::mesh_json(const TriMesh& mesh, const std::string& role,
                               const std::string& scalar) const {
  // For drawing only, so printed short: positions to 1 um, the scalar (the colour map) to 1e-4.
  // nlohmann::json keeps numbers as double, and a float widened to double prints 16 digits
  // ("-57.12300109863281"): the lab object's top view was 258 KB, 25 ms to build and send.
  // (x * 1000 rounded, then / 1000: the division is correctly rounded, so 57.123 prints as
  // such; "* 0.001" would give 57.123000000000005.)
  const auto round_to = [](double x, double per) { return std::round(x * per) / per; };
  std::vector<double> v;
  v.reserve(mesh.num_vertices() * 3);
  for (const Vec3& p : mesh.positions)
    for (int k = 0; k < 3; ++k) v.push_back(round_to(p[k], 1e3));
  std::vector<std::uint32_t> f;
  f.reserve(mesh.num_triangles() * 3);
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) f.push_back(static_cast<std::uint32_t>(t[k]));
  nlohmann::json j{{"type", "mesh"}, {"role", role}, {"vertices", v}, {"faces", f}};
  if (mesh.has_property(scalar)) {
    std::vector<double> s;
    for (double d : mesh.property(scalar)) s.push_back(round_to(d, 1e4));
    j["scalar"] = scalar;
    j["values"] = s;
  }
  return j.dump();
}

std::string Session::do_open_mesh(const Message& m) {
  const std::string source = get_choice(m, "source", {"study25", "workspace", "model"});
  TriMesh mesh;
  std::string name = source;
  std::shared_ptr<DataDrivenBundle> dd;
  if (source == "study25") {
    mesh = rendering::StudySurface(rendering::DatasetParams{}, rendering::identity_layout()).mesh();
  } else if (source == "workspace") {
    const std::string path = get_string(m, "path");
    mesh = read_workspace_mesh(workspace_, path);
    name = quote_input(std::filesystem::path(path).filename().string(), 200);
    if (!mesh.has_property("stiffness"))
      throw ProtocolError(fmt::format("{}: expected a vertex property \"stiffness\" (N/mm)", name));
  } else {  // a trained force model with its sliding yield surfaces and shape (inhap serve --render
            // model)
    const std::string model = get_string(m, "model"), shape = get_string(m, "shape");
    const WorkspacePath sys = workspace_.input(get_string(m, "sys"));
    const double radius = get_number_or(m, "probe_radius", 0, 50, 0);
    mesh = read_workspace_mesh(workspace_, shape);
    auto force = datadriven::force_model_from_json(workspace_.read(model), quote_input(model, 200));
    auto yield = with_names({&sys}, [&] { return friction::read_sys_json(sys.path()); });
    dd = std::make_shared<DataDrivenBundle>(std::move(force), std::move(yield), mesh, radius);
    name = quote_input(std::filesystem::path(model).filename().string(), 200);
  }
  // Everything loaded: only now does the session change.
  const std::string old_mode = mode();
  explore_mesh_ = std::move(mesh);
  explore_name_ = name;
  data_driven_ = std::move(dd);
  if (old_mode == "explore") {
    stop_rig();
    start_rig("explore");
  }
  // The page draws a light copy (top_view_mesh); the loop renders the mesh itself.
  nlohmann::json j = nlohmann::json::parse(
      mesh_json(top_view_mesh(explore_mesh_, "stiffness"), "explore", "stiffness"));
  j["faces_rendered"] = explore_mesh_.num_triangles();
  j["name"] = name;
  j["algorithm"] = data_driven_                               ? "data-driven"
                   : algorithm_ == rendering::Algorithm::kTCA ? "tca"
                                                              : "cba";
  return j.dump();
}

std::string Session::do_algorithm(const Message& m) {
  const std::string a = get_choice(m, "name", {"tca", "cba"});
  if (data_driven_)
    throw ProtocolError(
        "algorithm: the open model is data-driven; open a mesh with a stiffness map for TCA-MESH "
        "or CBA");
  algorithm_ = a == "tca" ? rendering::Algorithm::kTCA : rendering::Algorithm::kCBA;
  if (mode() == "explore") {
    stop_rig();
    start_rig("explore");
  }
  return nlohmann::json{{"type", "ok"}, {"request", "algorithm"}, {"name", a}}.dump();
}

// --- experiment ------------------------------------------------------------------------------

std::string Session::trial_json() const {
  const rendering::TrialSpec& s = schedule_[trial_];
  nlohmann::json centres = nlohmann::json::array();
  for (int c = 0; c < rendering::kNumModels; ++c)
    centres.push_back({surface_->cell_centre(c).x(), surface_->cell_centre(c).y()});
  return nlohmann::json{{"type", "trial"},
                        {"participant", participant_},
                        {"index", trial_},
                        {"trials", schedule_.size()},
                        {"session", s.session},
                        {"trial", s.trial},
                        {"task", rendering::to_string(s.task)},
                        {"centres", centres},
                        {"cell_mm", surface_->params().cell_mm},
                        {"size_mm", surface_->params().cell_mm * surface_->params().cells},
                        {"highlight_mm", rendering::ProtocolConfig{}.highlight_radius_mm},
                        {"answered", trial_answers_}}
      .dump();
}

std::string Session::do_experiment(const Message& m) {
  const int participant = static_cast<int>(get_integer(m, "participant", 0, 999));
  rendering::StudyConfig sc;
  sc.participants = participant + 1;
  sc.seed = options_.seed;
  schedule_ = rendering::participant_schedule(sc, participant);
  participant_ = participant;
  trial_ = 0;
  answers_.clear();
  trial_answers_.fill(-1);
  surface_.emplace(rendering::DatasetParams{},
                   rendering::shuffled_layout(schedule_[0].layout_seed));
  stop_rig();
  start_rig("experiment");
  write_answers();
  broadcast_trial();
  return trial_json();
}

std::string Session::do_answer(const Message& m) {
  if (!surface_ || mode() != "experiment") throw ProtocolError("answer: no experiment running");
  const int value = static_cast<int>(get_integer(m, "value", 0, 2));
  Vec3 hip;
  {
    std::lock_guard lock(data_mu_);
    if (!have_latest_) throw ProtocolError("answer: no probe position yet");
    hip = latest_.out.hip_mm;
  }
  const double r = rendering::ProtocolConfig{}.highlight_radius_mm;
  const int cell = surface_->cell_at(hip.x(), hip.y());
  if (cell < 0 || (surface_->cell_centre(cell) - hip.head<2>()).norm() > r)
    throw ProtocolError(
        fmt::format("answer: the probe is at no model (within {:g} mm of a centre)", r));
  const rendering::TrialSpec& spec = schedule_[trial_];
  Answer a;
  a.spec = spec;
  a.cell = cell;
  a.model = surface_->layout().model_at_cell[static_cast<std::size_t>(cell)];
  a.value = value;
  a.truth = spec.task == rendering::Task::kShape ? int(rendering::true_shape_class(a.model))
                                                 : int(rendering::true_stiffness_class(a.model));
  a.t_s = latest_.t_s;
  answers_.push_back(a);
  trial_answers_[static_cast<std::size_t>(cell)] = value;
  write_answers();
  broadcast_trial();
  return trial_json();
}

std::string Session::do_next_trial() {
  if (!surface_) throw ProtocolError("next_trial: no experiment running");
  if (trial_ + 1 >= schedule_.size()) throw ProtocolError("next_trial: this was the last trial");
  ++trial_;
  trial_answers_.fill(-1);
  surface_.emplace(rendering::DatasetParams{},
                   rendering::shuffled_layout(schedule_[trial_].layout_seed));
  stop_rig();
  start_rig("experiment");
  broadcast_trial();
  return trial_json();
}

// Every page gets the trial (the participant screen may be another window than the one that
// sent the command) and the progress (only the experimenter window shows it).
void Session::broadcast_trial() const {
  broadcast_(trial_json());
  broadcast_(progress_json());
}

std::string Session::progress_json() const {
  nlohmann::json j{{"type", "progress"}, {"running", surface_.has_value()}};
  if (!surface_) return j.dump();
  const rendering::TrialSpec& spec = schedule_[trial_];
  j.update({{"participant", participant_},
            {"index", trial_},
            {"trials", schedule_.size()},
            {"session", spec.session},
            {"trial", spec.trial},
            {"task", rendering::to_string(spec.task)},
            {"algorithm", rendering::to_string(spec.algorithm)},
            {"answered", std::count_if(trial_answers_.begin(), trial_answers_.end(),
                                       [](int a) { return a >= 0; })},
            {"answers", answers_.size()}});
  return j.dump();
}

void Session::write_answers() const {
  const std::string path = fmt::format("participant-{:03d}.csv", participant_);
  std::string out =
      "# inhap studio answers (thesis 5.4): label = ShapeClass (0 flat, 1 bump, 2 hole) or "
      "StiffnessClass (0 same, 1 harder, 2 softer); t s (device time)\n"
      "participant,session,trial,algorithm,task,layout_seed,cell,model,label,truth,correct,t\n";
  for (const Answer& a : answers_)
    out += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{:.3f}\n", participant_, a.spec.session,
                       a.spec.trial, rendering::to_string(a.spec.algorithm),
                       rendering::to_string(a.spec.task), a.spec.layout_seed, a.cell, a.model + 1,
                       a.value, a.truth, a.value == a.truth ? 1 : 0, a.t_s);
  workspace_.write(path, out);
}

}  // namespace inhap::studio

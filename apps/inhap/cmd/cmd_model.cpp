// inhap model train | eval | render: the data-driven force model of thesis sec. 4.4-4.5 (the work
// is inhap/eval/model_files.hpp). Units: positions mm, velocities mm/s, forces N, time s.
#include <fmt/format.h>

#include <memory>

#include "command.hpp"
#include "inhap/core/atomic_file.hpp"
#include "inhap/core/device.hpp"
#include "inhap/datadriven/coverage.hpp"
#include "inhap/datadriven/model_io.hpp"
#include "inhap/eval/model_files.hpp"
#include "model_flags.hpp"

namespace inhap::cli {
namespace {

using namespace inhap::datadriven;

void add_proxy_options(CLI::App* c, eval::ProxyColumnsSpec& o) {
  c->add_option("--proxy-prefix", o.prefix,
                "Proxy columns <prefix>x,<prefix>y,<prefix>z of the recording, mm (written by the "
                "proxy estimator); 'p' = the probe itself (q = p). Without proxy columns (and "
                "without this flag) the surface, normals, proxy and friction are estimated from "
                "the recording")
      ->capture_default_str();
  c->add_option("--contact-column", o.contact_column,
                "Contact flag column (non-zero = contact); when absent, contact = |f| above "
                "--contact-threshold")
      ->capture_default_str();
  c->add_option("--contact-threshold", o.contact_threshold_n, "Force magnitude for contact, N")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
}

void add_unit_options(CLI::App* c, eval::RecordingUnits& u) {
  c->add_option("--time-unit", u.time, "Unit of the recording's t column: s or ms")
      ->capture_default_str()
      ->check(CLI::IsMember({"s", "ms"}));
  c->add_option("--length-unit", u.length,
                "Unit of the recording's px,py,pz (and qx,qy,qz) columns: mm or m")
      ->capture_default_str()
      ->check(CLI::IsMember({"mm", "m"}));
}

struct TrainOptions {  // inhap model train
  eval::TrainFileOptions file;
  std::string out;
  bool verbose = false;
};

void run_train(TrainOptions o) {
  o.file.progress = progress;
  o.file.on_note = [](const std::string& note) { fmt::print(stderr, "inhap: {}\n", note); };
  eval::TrainFileResult r = eval::train_from_file(o.file);
  if (r.estimate)
    for (const std::string& f : eval::write_estimate_files(o.out, *r.estimate, r.model.provenance))
      fmt::print(stderr, "inhap: wrote {}\n", f);
  save_force_model(o.out, r.model);
  fmt::print(stderr, "inhap: {}\n",
             eval::range_note(r.model.provenance, r.set, o.file.force_limit_n));
  for (const std::string& line : eval::write_training_coverage(r.set, coverage_path_for(o.out)))
    fmt::print(stderr, "inhap: {}\n", line);
  fmt::print("{}model -> {}\n", eval::train_summary(r.model, o.verbose), o.out);
}

struct ReplayOptions {  // inhap model eval | render
  std::string model, recording, json, out, mesh, train;
  eval::ProxyColumnsSpec proxy;
  eval::RecordingUnits units;
};

void run_eval(const ReplayOptions& o) {
  const eval::ModelEvalResult r =
      eval::evaluate_model_file(o.model, o.recording, o.proxy, o.mesh, o.units, o.train);
  fmt::print(stderr, "inhap: {}\n", eval::support_note(r.support));
  if (!r.baselines_note.empty()) fmt::print(stderr, "inhap: {}\n", r.baselines_note);
  if (!o.json.empty()) write_file_atomic(o.json, r.json.dump(1) + "\n");
  fmt::print("{}", eval::model_eval_text(r));
}

void run_render(const ReplayOptions& o) {
  const TrainedForceModel m = load_trained_force_model(o.model);
  const eval::ReplayedFile r = eval::replay_file(o.model, m, o.recording, o.proxy, o.mesh, o.units);
  fmt::print(stderr, "inhap: {}\n", eval::support_note(eval::support_share(o.model, r)));
  eval::write_rendered_csv(o.out, r, o.recording, o.model);
  fmt::print("{} samples rendered -> {}\n", r.rec.size(), o.out);
}

// The fit's flags (bins, centres, solver, features, priors); their defaults come from the preset.
void add_fit_options(CLI::App& ct, eval::TrainRequest& q) {
  ct.add_option("--bins", q.params.bins, "Bins by ||q - p|| (equal counts; default: preset)")
      ->capture_default_str()
      ->check(CLI::Range(1, 100));
  ct.add_option("--centers", q.params.centers, "M: k-means clusters (selected samples) per bin")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  ct.add_option("--nonzeros", q.params.nonzeros, "Wanted non-zeros per axis (0 = M)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  ct.add_option("--lambda-ratio", q.params.lambda_ratio, "lambda = ratio * ||A~^T f~||_inf")
      ->capture_default_str();
  ct.add_option("--seed", q.params.seed, "Seed of the k-means++ draws")->capture_default_str();
  ct.add_option("--design", q.design,
                "thesis: A~ is M x N_bin (rows = selected samples, sec. 4.4.2); regression: A~ is "
                "N_bin x M (rows = every sample, columns = selected samples); default: preset")
      ->capture_default_str()
      ->check(CLI::IsMember({"thesis", "regression"}));
  ct.add_option("--features", q.features,
                "ue_q_v = (q - p, q, pdot); p_v_q = (p, pdot, q); local = (q - p, q, pdot) with "
                "q - p, pdot and the force in the surface frame at q (normals from columns "
                "nx,ny,nz or from --mesh); default: preset")
      ->capture_default_str()
      ->check(CLI::IsMember({"ue_q_v", "p_v_q", "local"}));
  add_switch(
      ct, "tail", q.params.linear_tail,
      "Linear polynomial tail on every expansion (the thesis has none; default: preset, on in "
      "best and world, off in thesis)",
      false);
  add_local_training_flags(ct, q.params, "default: preset; on in best, off in world and thesis");
  ct.add_option("--feature-weights", q.params.feature_weights,
                "Weights of the three feature groups after standardisation (default: preset; "
                "best 1 5 0.5)");
  ct.add_option("--bin-blend", q.params.bin_blend,
                "Half-width of the blend band around bin edges, mm of ||q - p|| (0: hard "
                "switch; default: preset)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  ct.add_option("--threads", q.params.threads, "Worker threads (0 = all cores)")
      ->capture_default_str();
}

// inhap model train: the flags and the preset bookkeeping (which flags were given).
void register_train(CLI::App& model) {
  auto tr = std::make_shared<TrainOptions>();
  eval::TrainFileOptions& f = tr->file;
  eval::TrainRequest& q = f.request;
  auto* ct = model.add_subcommand(
      "train",
      "Train a model from a recording (writes model JSON). With no flags: preset 'best', the "
      "documented pipeline\n(local-frame features, tangent mirror, stiffness and shear priors, "
      "friction cone, feature weights 1 5 0.5,\nbin blend 1 mm; needs normals nx,ny,nz or "
      "--mesh, else preset 'world' with a note). Options given\nexplicitly override the "
      "preset. Forces above --modeling-range are counted and reported, never clipped.");
  ct->add_option("--recording", f.recording,
                 "Recording CSV: t,px,py,pz,fx,fy,fz (s, mm, N; see --time-unit, --length-unit), "
                 "any rate, extra columns ignored; optional proxy qx,qy,qz (mm), contact, "
                 "nx,ny,nz")
      ->required();
  add_unit_options(ct, f.units);
  ct->add_option("--velocity-window", f.velocity_window_s,
                 "FOAW velocity window cap, s (samples = window x rate; --foaw-window overrides)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  ct->add_option("--sys", f.sys, "Sliding-yield-surface file to reference in the model");
  ct->add_option("--mesh", f.mesh, "Shape mesh to reference in the model");
  ct->add_option("--out", tr->out, "Model file to write (.json)")->required();
  ct->add_option("--preset", q.preset,
                 "best = the documented pipeline; world = world-frame (q - p, q, pdot) features, "
                 "no priors (no normals needed); thesis = the thesis' settings (sec. 4.4: world "
                 "frame, 5 bins, no tail, M x N design, equal weights)")
      ->capture_default_str()
      ->check(CLI::IsMember(preset_names()));
  ct->add_option("--modeling-range", q.params.modeling_range_n,
                 "Modeling range, N: samples with |f| above it are counted and reported, and "
                 "kept or excluded (--above-range)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  ct->add_option("--above-range", q.above_range,
                 "keep = train on forces above the modeling range as measured; exclude = leave "
                 "those samples out (either way counted and reported; nothing is clipped)")
      ->capture_default_str()
      ->check(CLI::IsMember({"keep", "exclude"}));
  add_fit_options(*ct, q);
  ct->add_option("--foaw-window", f.foaw.max_window, "FOAW window cap, samples")
      ->capture_default_str()
      ->check(CLI::Range(1, kFoawMaxWindow - 1));
  ct->add_option("--foaw-noise", f.foaw.noise_bound_mm, "FOAW noise bound d, mm")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  ct->add_option("--force-limit", f.force_limit_n,
                 fmt::format("Rendered force clamp, N (may lower the device's {} N, never "
                             "raise it; the training data are not clipped)",
                             kDeviceForceLimitN))
      ->capture_default_str()
      ->check(CLI::Range(1e-9, kDeviceForceLimitN));
  add_proxy_options(ct, f.proxy);
  ct->add_flag("--verbose", tr->verbose,
               "Print the CPU time of each training stage (s, summed over threads)");
  ct->callback([tr, ct] {
    for (const CLI::Option* opt : ct->get_options())
      if (opt->count() > 0)
        for (const std::string& name : opt->get_lnames())  // --no-x counts as --x given
          tr->file.request.given.insert("--" + (name.rfind("no-", 0) == 0 ? name.substr(3) : name));
    run_train(*tr);
  });
}

void register_model(CLI::App& app) {
  auto* model = app.add_subcommand(
      "model",
      "Data-driven force model f = g(p, pdot, q) (thesis 4.4): r^3 RBFs per ||q - p|| bin.\n"
      "Recordings: t,px,py,pz,fx,fy,fz (s, mm, N) at any rate; proxy columns qx,qy,qz (mm) when\n"
      "they have them, else the surface, normals, proxy and friction are estimated from the\n"
      "recording (docs/real-recordings.md). Contact from a column or a force threshold.");
  model->require_subcommand(1);
  register_train(*model);
  // eval and render: a trained model replayed over a recording
  for (const bool render : {false, true}) {
    auto o = std::make_shared<ReplayOptions>();
    auto* c = model->add_subcommand(
        render ? "render" : "eval",
        render ? "Replay a recording at servo rate; write rendered forces (N)"
               : "Replay a recording through the servo renderer; errors (eq. 4.27-4.31)");
    c->add_option("--model", o->model, "Model JSON")->required();
    c->add_option(
         "--recording", o->recording,
         render ? "Recording CSV with proxy columns" : "Test recording CSV with proxy columns")
        ->required();
    if (render)
      c->add_option("--out", o->out,
                    "CSV to write: t,px,py,pz,fx,fy,fz (rendered),mfx,mfy,mfz (measured),contact")
          ->required();
    else {
      c->add_option("--json", o->json, "Write the error report (N) as JSON here");
      c->add_option("--train", o->train,
                    "Training recording to fit the baselines on (mean force, k-nearest "
                    "neighbours on p and on (p, 0.1 s x pdot)); default: the one the model names");
    }
    add_proxy_options(c, o->proxy);
    add_unit_options(c, o->units);
    c->add_option("--mesh", o->mesh,
                  "Shape mesh for the normals of a local-frame model (default: the model's)");
    c->callback([o, render] { render ? run_render(*o) : run_eval(*o); });
  }
}

}  // namespace

INHAP_COMMAND(40, "model", register_model);

}  // namespace inhap::cli

// inhap eval recordings: train the force model on one recording, render another and score it
// beside the baselines (the work: eval/recordings_eval.hpp). Units: mm, N, s.
#include <fmt/format.h>

#include "command.hpp"
#include "inhap/core/atomic_file.hpp"
#include "inhap/eval/recordings_eval.hpp"

namespace inhap::cli {
namespace {

struct EvalRecordingsOptions {
  eval::TrainFileOptions file;
  std::string test, json, csv, svg;
};

void run_eval_recordings(EvalRecordingsOptions& o) {
  o.file.progress = progress;
  o.file.on_note = [](const std::string& note) { fmt::print(stderr, "inhap: {}\n", note); };
  const eval::RecordingsEval e = eval::evaluate_recordings(o.file, o.test);
  fmt::print("train {} ({:.1f} Hz, trained in {:.1f} s), test {}\n", o.file.recording, e.rate_hz,
             e.train.model.provenance.stats.seconds, o.test);
  fmt::print("{}", eval::baseline_text(e.report));
  if (!o.json.empty()) write_file_atomic(o.json, eval::recordings_json(e, o.test).dump(1) + "\n");
  if (!o.csv.empty()) eval::write_recordings_csv(o.csv, e);
  if (!o.svg.empty()) eval::write_recordings_svg(o.svg, e);
}

void register_eval_recordings(CLI::App& app) {
  auto o = std::make_shared<EvalRecordingsOptions>();
  auto* c = eval_group(app)->add_subcommand(
      "recordings",
      "Train the force model on one recording (as `model train` with no flags: the surface, "
      "normals, proxy\nand friction estimated when it has no proxy columns), render another "
      "and score both beside the\nbaselines fitted on the training recording: mean force, "
      "k-nearest neighbours (k = 5) on p and on\n(p, 0.1 s x pdot). Says whether the model "
      "beats them. Units: t s, p mm, f N (see --time-unit,\n--length-unit).");
  c->add_option("--train", o->file.recording, "Training recording CSV")->required();
  c->add_option("--test", o->test, "Test recording CSV (another trial of the same object)")
      ->required();
  c->add_option("--json", o->json,
                "Write {model, baselines, verdict, rate_hz, estimated, ...} as JSON here");
  c->add_option("--csv", o->csv,
                "Write measured vs rendered force per axis (model and the best baseline) here");
  c->add_option("--plot", o->svg,
                "Draw measured vs rendered force per axis (model and the best baseline) over the "
                "first 20 s of the test recording: SVG file");
  c->add_option("--preset", o->file.request.preset, "Training preset (see model train)")
      ->capture_default_str();
  c->add_option("--time-unit", o->file.units.time, "s or ms")->capture_default_str();
  c->add_option("--length-unit", o->file.units.length, "mm or m")->capture_default_str();
  c->add_option("--contact-threshold", o->file.proxy.contact_threshold_n,
                "Force magnitude for contact, N")
      ->capture_default_str();
  c->add_option("--threads", o->file.request.params.threads, "Worker threads (0 = all cores)");
  c->callback([o, c] {
    for (const CLI::Option* opt : c->get_options())
      if (opt->count() > 0 && opt->get_lnames().front() != "train")
        for (const std::string& name : opt->get_lnames()) o->file.request.given.insert("--" + name);
    run_eval_recordings(*o);
  });
}

}  // namespace

INHAP_COMMAND(63, "eval recordings", register_eval_recordings);

}  // namespace inhap::cli

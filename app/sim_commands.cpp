// proprio sim ...: the simulated robot world (issue 3): record episodes, calibrate the simulated
// camera, render a scene.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <opencv2/imgcodecs.hpp>

#include "cli.hpp"
#include "option_binder.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"
#include "proprio/sim/calibration.hpp"
#include "proprio/sim/dataset.hpp"
#include "proprio/sim/recorder.hpp"
#include "proprio/sim/scenario_view.hpp"
#include "proprio/sim/sim_runs.hpp"
#include "proprio/sim/views.hpp"

namespace proprio::app {
namespace {
namespace fs = std::filesystem;

struct RecordArgs {
  sim::RecordOptions options;
  std::string background = "static";
  int distractors = -1;
  std::string out;
  JsonFlag json;
};

void add_scene_options(CLI::App* cmd, RecordArgs& a) {
  cmd->add_option("--scenario", a.options.scenario,
                  "push, push-rotate, clutter, scatter, hold-3d, or a scene FILE.json / FILE.yaml")
      ->capture_default_str();
  cmd->add_option("--object", a.options.object, "Target object (catalogue name)")
      ->capture_default_str();
  cmd->add_option("--background", a.background, "static, or moving (video backdrop + distractors)")
      ->check(CLI::IsMember({"static", "moving"}))
      ->capture_default_str();
  cmd->add_option("--seed", a.options.seed, "Seed of the random placement")->capture_default_str();
  cmd->add_option("--clutter", a.options.clutter, "Other objects placed at random")
      ->capture_default_str();
  cmd->add_option("--scatter-objects", a.options.scatter_objects,
                  "Scatter: exactly these objects (catalogue names, the --object among them); "
                  "the others wander over the table in and out of view")
      ->delimiter(',');
  cmd->add_flag("--scatter-in-view", a.options.scatter_in_view,
                "Scatter objects keep inside the camera's view (else they leave it and return)");
  cmd->add_option("--width", a.options.width, "Image width, pixels")->capture_default_str();
  cmd->add_option("--height", a.options.height, "Image height, pixels")->capture_default_str();
  cmd->add_flag("--shadows", a.options.shadows, "Render shadows (slower)");
  cmd->add_option("--distractors", a.distractors,
                  "Moving distractor objects (default: 2 with a moving background, else 0)");
  cmd->add_flag("--stereo", a.options.stereo, "Also a right camera (--baseline apart)");
  cmd->add_option("--baseline", a.options.stereo_baseline,
                  "Stereo baseline, m (distance between the camera centres)")
      ->capture_default_str();
  cmd->add_flag("--nudge-neighbour", a.options.nudge_neighbour,
                "A neighbouring object is shoved sideways during the push");
}

// The options as given, with the derived ones filled in.
sim::RecordOptions resolved(const RecordArgs& a) {
  sim::RecordOptions o = a.options;
  o.moving_background = a.background == "moving";
  if (a.distractors >= 0) o.distractors = a.distractors;
  return o;
}

void run_record(RecordArgs& a, const Invocation& inv) {
  a.options = resolved(a);
  a.json.refuse({a.out, a.options.background_video});
  const sim::SimRun r = sim::run_sim_record(a.options, a.out, inv.provenance(a.options.seed));
  std::fputs(r.brief().c_str(), stdout);
  a.json.write(r.document);
}

struct CalibrateArgs {
  sim::SimCalibrationOptions options;
  std::string out;
  JsonFlag json;
};

void run_calibrate(const CalibrateArgs& a, const Invocation& inv) {
  a.json.refuse({a.out});
  const sim::SimRun r = sim::run_sim_calibrate(a.options, a.out, inv.provenance());
  std::fputs(r.brief().c_str(), stdout);
  a.json.write(r.document);
}

void run_view(const RecordArgs& a) {
  const sim::RecordOptions o = resolved(a);
  core::require_output_not_input(a.out, {o.background_video}, "--out");
  const cv::Mat rgb = sim::render_scenario_view(o, sim::ObjectCatalogue::load_default());
  std::vector<uchar> png;
  if (!cv::imencode(".png", rgb, png)) throw Error::in_file(a.out, "cannot encode the image");
  core::write_file_atomic(a.out,
                          std::string_view(reinterpret_cast<const char*>(png.data()), png.size()));
  std::printf("view: %s\n", a.out.c_str());
}

struct DatasetArgs {
  sim::SimDatasetOptions options;
  bool quiet = false;
  JsonFlag json;
};

struct ViewsArgs {
  sim::ViewsOptions options;
  std::string objects = "book,mug";
  std::string out;
  JsonFlag json;
};

void run_views(ViewsArgs& a, const Invocation& inv) {
  a.options.objects.clear();
  std::size_t start = 0;
  while (start <= a.objects.size()) {
    const std::size_t comma = std::min(a.objects.find(',', start), a.objects.size());
    if (comma > start) a.options.objects.push_back(a.objects.substr(start, comma - start));
    start = comma + 1;
  }
  std::vector<std::filesystem::path> paths = a.options.backgrounds;
  paths.emplace_back(a.out);
  a.json.refuse(paths);
  const sim::SimRun r = sim::run_sim_views(a.options, a.out, inv.provenance(a.options.seed));
  std::fputs(r.brief().c_str(), stdout);
  a.json.write(r.document);
}

}  // namespace

void register_sim_commands(CLI::App& root, const Invocation& inv) {
  auto* sim = root.add_subcommand("sim", "The simulated robot world: record, calibrate, view");
  sim->require_subcommand(1);

  auto rec = std::make_shared<RecordArgs>();
  auto* record = sim->add_subcommand("record", "Record one simulated episode (thesis 5.1-5.2)");
  add_scene_options(record, *rec);
  record->add_option("--out", rec->out, "Episode directory to create")->required();
  record->add_option("--fps", rec->options.fps, "Frame rate")->capture_default_str();
  record->add_option("--speed", rec->options.push_speed, "Push speed, m/s")->capture_default_str();
  record->add_flag("--overwrite", rec->options.overwrite, "Replace an existing episode at --out");
  record->add_flag("--camera-shake", rec->options.camera_shake, "The camera trembles");
  record->add_flag("--lighting-change", rec->options.lighting_change,
                   "The main light moves half-way through");
  record->add_option("--noise", rec->options.noise, "Gaussian image noise, sigma in grey levels");
  record->add_flag("--motion-blur", rec->options.motion_blur,
                   "Average 4 renders over each frame's interval");
  record->add_flag("--depth", rec->options.depth, "Also depth images (16-bit mm)");
  rec->json.add_to(record, "frames, seconds, fps");
  record->callback([rec, &inv] { run_record(*rec, inv); });

  auto cal = std::make_shared<CalibrateArgs>();
  auto* calibrate = sim->add_subcommand(
      "calibrate", "Robot-camera calibration in simulation (thesis 3.2.3): marker grid + DLT");
  calibrate->add_option("--out", cal->out, "calib.yml to write")->required();
  calibrate->add_option("--grid", cal->options.grid, "Grid points per axis")->capture_default_str();
  cal->json.add_to(calibrate, "rms_px, true_error_px");
  calibrate->callback([cal, &inv] { run_calibrate(*cal, inv); });

  auto ds = std::make_shared<DatasetArgs>();
  auto* dataset = sim->add_subcommand("dataset", "Record a preset set of episodes");
  dataset->add_option("--preset", ds->options.preset, "Preset")
      ->check(CLI::IsMember({"thesis-ch5"}))
      ->capture_default_str();
  dataset->add_option("--out", ds->options.out, "Directory to create")->required();
  bind_options(dataset, ds->options);
  dataset->add_flag("-q,--quiet", ds->quiet, "No progress bar");
  ds->json.add_to(dataset, "the episode list");
  dataset->callback([ds, &inv] {
    ds->options.progress = !ds->quiet;
    ds->json.refuse({ds->options.out});
    const sim::SimDatasetResult r =
        sim::run_sim_dataset(ds->options, inv.provenance(ds->options.seed));
    std::printf("dataset: %s\n%s\n", ds->options.out.c_str(), r.brief().c_str());
    ds->json.write(r.document);
  });

  auto vs = std::make_shared<ViewsArgs>();
  auto* views = sim->add_subcommand(
      "views", "Folder-per-class images: each object alone, many viewpoints, real backdrops");
  views->add_option("--objects", vs->objects, "Comma-separated catalogue names")
      ->capture_default_str();
  views->add_option("--per-object", vs->options.per_object, "Images per object")
      ->capture_default_str();
  views->add_option("--width", vs->options.width, "Image width")->capture_default_str();
  views->add_option("--height", vs->options.height, "Image height")->capture_default_str();
  views->add_option("--seed", vs->options.seed, "Seed")->capture_default_str();
  views->add_flag("--masks", vs->options.masks,
                  "Also the object's ground-truth mask as each image's alpha channel "
                  "(read by --alpha-mask)");
  views->add_option("--out", vs->out, "Directory to create")->required();
  vs->json.add_to(views, "a summary");
  views->callback([vs, &inv] { run_views(*vs, inv); });

  auto vw = std::make_shared<RecordArgs>();
  auto* view = sim->add_subcommand("view", "Render one picture of a scenario's scene");
  add_scene_options(view, *vw);
  view->add_option("--out", vw->out, "PNG file to write")->required();
  view->callback([vw] { run_view(*vw); });
}

}  // namespace proprio::app

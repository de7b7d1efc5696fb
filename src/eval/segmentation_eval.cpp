#include "proprio/eval/segmentation_eval.hpp"

#include <algorithm>
#include <array>
#include <cassert>
#include <chrono>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include "proprio/core/csv.hpp"
#include "proprio/core/error.hpp"

namespace proprio::eval {
namespace fs = std::filesystem;
namespace seg = proprio::segmentation;

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

const std::vector<std::pair<Method, std::string>>& method_names() {
  static const std::vector<std::pair<Method, std::string>> kNames = {
      {Method::kMl, "ml"},
      {Method::kMlHomography, "ml-homography"},
      {Method::kMlSparse, "ml-sparse"},
      {Method::kFm, "fm"},
      {Method::kMlGraphCut, "ml-graphcut"},
      {Method::kMlDepth, "ml-depth"}};
  return kNames;
}

// The target's ground truth at frame i, or an empty Mat when there is none (no masks, no target,
// or the target not visible).
cv::Mat1b truth_at(const episode::Episode& ep, int i) {
  if (!ep.info().has_masks || !ep.info().target || i < 0 || i >= ep.frame_count()) return {};
  cv::Mat1b t = ep.mask(i) == *ep.info().target;
  if (cv::countNonZero(t) == 0) return {};
  return t;
}

// Scores `mask` against the truth at the scored frame; sweeps by `mask_at(value)`.
template <typename MaskAt>
void score(MethodOutcome& o, const cv::Mat1b& truth, const cv::Mat1b& mask,
           const std::vector<double>& sweep, MaskAt mask_at) {
  o.status = "ok";
  o.metrics = compare_masks(mask, truth);
  for (double v : sweep) {
    const MaskMetrics m = compare_masks(mask_at(v), truth);
    o.sweep_precision.push_back(m.precision);
    o.sweep_recall.push_back(m.recall);
  }
}

std::string switch_string(const core::Json& switches, const char* key) {
  if (switches.is_object() && switches.contains(key) && switches[key].is_string()) {
    return switches[key].get<std::string>();
  }
  return {};
}

// join_csv_line does not quote: keep commas and line breaks out of free text.
std::string csv_text(std::string s) {
  for (char& c : s) {
    if (c == ',' || c == '\n' || c == '\r') c = ';';
  }
  return s;
}

std::string fmt(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

}  // namespace

std::string to_string(Method m) {
  for (const auto& [k, v] : method_names()) {
    if (k == m) return v;
  }
  return "?";
}

Method parse_method(const std::string& s) {
  for (const auto& [k, v] : method_names()) {
    if (v == s) return k;
  }
  std::string msg = "unknown segmentation method '" + s;
  msg += "' (ml, ml-homography, ml-sparse, fm, ml-graphcut, ml-depth)";
  throw Error(msg);
}

std::vector<Method> parse_methods(const std::string& list) {
  std::vector<Method> out;
  std::stringstream in(list);
  std::string item;
  while (std::getline(in, item, ',')) {
    if (item.empty()) continue;
    const Method m = parse_method(item);
    require(std::find(out.begin(), out.end(), m) == out.end(), "method '" + item + "' given twice");
    out.push_back(m);
  }
  require(!out.empty(), "no segmentation method given");
  return out;
}

std::string free_parameter(Method m) {
  return m == Method::kFm ? "difference_threshold" : "mask_fraction";
}

void EvalOptions::validate() const {
  ml.validate();
  sparse.validate();
  fm.validate();
  ml_graph_cut.validate();
  require(!fraction_sweep.empty() && !threshold_sweep.empty(), "eval: empty parameter sweep");
  for (double f : fraction_sweep) {
    require(std::isfinite(f) && f > 0 && f <= 1, "eval: sweep fractions must be in (0, 1]");
  }
  for (double t : threshold_sweep) {
    require(std::isfinite(t) && t >= 0 && t < 255, "eval: sweep thresholds must be in [0, 255)");
  }
  require(bootstrap_resamples >= 1 && bootstrap_resamples <= 1000000,
          "eval: bootstrap resamples must be 1..1000000");
}

EpisodeEvaluation evaluate_episode(const episode::Episode& ep, const std::vector<Method>& methods,
                                   const EvalOptions& options, bool keep_images) {
  options.validate();
  if (ep.frame_count() < 1) throw Error::in_file(ep.dir(), "the episode has no frames");
  if (static_cast<int>(ep.arm().size()) != ep.frame_count()) {
    throw Error::in_file(ep.dir(), "the episode has no arm sample for every frame");
  }
  EpisodeEvaluation e;
  e.dir = ep.dir();
  e.name = ep.dir().filename().string();
  if (e.name.empty()) e.name = ep.dir().parent_path().filename().string();
  const auto& prov = ep.info().provenance;
  e.scenario = prov.scenario.value_or("");
  e.background = switch_string(prov.switches, "background");
  if (e.background != "static" && e.background != "moving") e.background = "unknown";
  if (ep.info().target && ep.object(*ep.info().target)) {
    e.object = ep.object(*ep.info().target)->name;
  } else {
    e.object = switch_string(prov.switches, "object");
  }
  e.first_touch_frame = ep.first_touch_frame();

  // M-L (translation) runs once when both ml and ml-graphcut are asked for.
  std::optional<seg::MlResult> ml_cache;
  double ml_seconds = 0;
  auto run_ml = [&](Method m) {
    seg::MlOptions mo = options.ml;
    mo.model =
        m == Method::kMlHomography ? seg::MotionModel::kHomography : seg::MotionModel::kTranslation;
    mo.use_depth = m == Method::kMlDepth;
    mo.keep_frame_maps = options.all_frames;
    return seg::segment_ml(ep, mo);
  };
  const auto& fractions = options.fraction_sweep;

  for (Method m : methods) {
    MethodOutcome o;
    o.method = m;
    const auto t0 = Clock::now();
    try {
      if (m == Method::kMl || m == Method::kMlHomography || m == Method::kMlSparse ||
          m == Method::kMlDepth) {
        seg::MlResult r;
        double fraction = m == Method::kMlDepth ? options.ml.depth_mask_fraction > 0
                                                      ? options.ml.depth_mask_fraction
                                                      : options.ml.mask_fraction
                                                : options.ml.mask_fraction;
        if (m == Method::kMlSparse) {
          r = seg::segment_ml_sparse(ep, options.sparse);
          fraction = options.sparse.mask_fraction;
        } else {
          r = run_ml(m);
        }
        o.scored_frame = r.scored_frame;
        o.message = r.summary.message;
        if (r.scored_frame < 0) {
          o.status = "no touch";
        } else {
          const cv::Mat1b truth = truth_at(ep, r.scored_frame);
          if (truth.empty()) {
            o.status = "no ground truth";
          } else {
            score(o, truth, r.mask, fractions,
                  [&](double f) { return seg::threshold_map(r.map, f); });
          }
          if (options.all_frames && !r.frame_maps.empty()) {
            double sum = 0;
            for (int i = r.scored_frame; i < static_cast<int>(r.frame_maps.size()); ++i) {
              const cv::Mat1b t = truth_at(ep, i);
              if (t.empty()) continue;
              sum += compare_masks(
                         seg::threshold_map(r.frame_maps[static_cast<std::size_t>(i)], fraction), t)
                         .jaccard;
              ++o.all_frames_count;
            }
            if (o.all_frames_count > 0) o.all_frames_jaccard = sum / o.all_frames_count;
          }
          if (keep_images) {
            o.map = r.map;
            o.mask = r.mask;
            o.frame = ep.frame(r.scored_frame);
          }
        }
        r.frame_maps.clear();
        if (m == Method::kMl) {
          ml_seconds = seconds_since(t0);
          ml_cache = std::move(r);
        }
      } else if (m == Method::kFm) {
        const seg::FmFrames frames = seg::load_fm_frames(ep, options.fm);
        const seg::FmResult r = seg::segment_fm(frames, options.fm);
        o.scored_frame = r.scored_frame;
        o.message = r.summary.message;
        if (r.scored_frame < 0) {
          o.status = ep.first_touch_frame() ? "failed" : "no touch";
        } else {
          const cv::Mat1b truth = truth_at(ep, r.scored_frame);
          if (truth.empty()) {
            o.status = "no ground truth";
          } else {
            score(o, truth, r.mask, options.threshold_sweep, [&](double t) {
              seg::FmOptions fo = options.fm;
              fo.difference_threshold = t;
              if (fo.touch == seg::TouchSource::kDifferencing) {
                const seg::FmResult rr = seg::segment_fm(ep, fo);
                // A different touch frame is scored against the truth at frame t regardless.
                return rr.mask.empty() ? cv::Mat1b(truth.size(), uchar(0)) : rr.mask;
              }
              const seg::FmResult rr = seg::segment_fm(frames, fo);
              return rr.mask.empty() ? cv::Mat1b(truth.size(), uchar(0)) : rr.mask;
            });
          }
          if (keep_images) {
            o.mask = r.mask;
            o.frame = frames.touch;
            // The map of the baseline: its motion evidence (255), the arm model (96).
            cv::Mat1f map(r.motion.size(), 0.f);
            map.setTo(1.f, r.motion);
            map.setTo(0.375f, r.arm);
            o.map = map;
          }
        }
      } else {  // kMlGraphCut
        if (!ml_cache) {
          ml_cache = run_ml(Method::kMl);
          ml_cache->frame_maps.clear();
          ml_seconds = seconds_since(t0);
        }
        const seg::MlResult& r = *ml_cache;
        o.scored_frame = r.scored_frame;
        if (r.scored_frame < 0) {
          o.status = "no touch";
          o.message = r.summary.message;
        } else {
          const cv::Mat frame = ep.frame(r.scored_frame);
          const auto cut = seg::ml_graph_cut(frame, r.map, options.ml_graph_cut);
          o.message = cut.summary.message;
          const cv::Mat1b truth = truth_at(ep, r.scored_frame);
          if (truth.empty()) {
            o.status = "no ground truth";
          } else {
            score(o, truth, cut.mask, fractions, [&](double f) {
              seg::MlGraphCutOptions go = options.ml_graph_cut;
              go.mask_fraction = f;
              return seg::ml_graph_cut(frame, r.map, go).mask;
            });
          }
          if (keep_images) {
            o.map = r.map;
            o.mask = cut.mask;
            o.frame = frame;
          }
        }
      }
    } catch (const Error& err) {
      o.status = "failed";
      o.message = err.what();
    }
    o.seconds = seconds_since(t0);
    // ml-graphcut's time includes the M-L run it refines.
    if (m == Method::kMlGraphCut && ml_cache &&
        std::find(methods.begin(), methods.end(), Method::kMl) != methods.end()) {
      o.seconds += ml_seconds;
    }
    e.outcomes.push_back(std::move(o));
  }
  return e;
}

GroupSummary summarise(const std::vector<EpisodeEvaluation>& episodes, std::size_t method_index,
                       const std::vector<double>& sweep_values, const EvalOptions& options,
                       const std::string& background, const std::string& object,
                       const std::string& scenario) {
  GroupSummary g;
  g.sweep_values = sweep_values;
  g.pr_precision.assign(sweep_values.size(), 0.0);
  g.pr_recall.assign(sweep_values.size(), 0.0);
  std::vector<double> precision, recall, l2, all_frames, seconds;
  for (const EpisodeEvaluation& e : episodes) {
    if (background != kAnyGroup && e.background != background) continue;
    if (object != kAnyGroup && e.object != object) continue;
    if (scenario != kAnyGroup && e.scenario != scenario) continue;
    assert(method_index < e.outcomes.size());
    const MethodOutcome& o = e.outcomes[method_index];
    seconds.push_back(o.seconds);
    if (o.status == "no touch") ++g.no_touch;
    if (o.status == "no ground truth") ++g.no_ground_truth;
    if (o.status == "failed") ++g.failed;
    if (o.all_frames_jaccard) all_frames.push_back(*o.all_frames_jaccard);
    if (o.status != "ok") continue;
    ++g.episodes;
    g.jaccards.push_back(o.metrics.jaccard);
    precision.push_back(o.metrics.precision);
    recall.push_back(o.metrics.recall);
    l2.push_back(o.metrics.l2);
    for (std::size_t k = 0; k < sweep_values.size() && k < o.sweep_precision.size(); ++k) {
      g.pr_precision[k] += o.sweep_precision[k];
      g.pr_recall[k] += o.sweep_recall[k];
    }
  }
  g.mean_jaccard = mean(g.jaccards);
  g.std_jaccard = stddev(g.jaccards);
  g.mean_tanimoto = g.episodes > 0 ? 1.0 - g.mean_jaccard : 0.0;
  g.jaccard_ci95 =
      bootstrap_mean_interval(g.jaccards, 0.95, options.bootstrap_resamples, options.seed);
  g.mean_precision = mean(precision);
  g.mean_recall = mean(recall);
  g.mean_l2 = mean(l2);
  g.std_l2 = stddev(l2);
  g.mean_seconds = mean(seconds);
  if (!all_frames.empty()) g.mean_jaccard_all_frames = mean(all_frames);
  g.all_frames_episodes = static_cast<int>(all_frames.size());
  if (g.episodes > 0) {
    double best = 1e9;
    for (std::size_t k = 0; k < sweep_values.size(); ++k) {
      g.pr_precision[k] /= g.episodes;
      g.pr_recall[k] /= g.episodes;
      const double d = std::hypot(1.0 - g.pr_precision[k], 1.0 - g.pr_recall[k]);
      if (d < best) {
        best = d;
        g.pr_best = static_cast<int>(k);
      }
    }
  }
  return g;
}

DatasetSummary dataset_summary(const std::vector<EpisodeEvaluation>& episodes,
                               const std::vector<Method>& methods, const EvalOptions& options) {
  std::set<std::string> objects, scenarios;
  for (const auto& e : episodes) {
    objects.insert(e.object);
    scenarios.insert(e.scenario);
  }
  DatasetSummary out;
  std::vector<const MethodSummary*> summaries;
  for (std::size_t k = 0; k < methods.size(); ++k) {
    const auto& sweep =
        methods[k] == Method::kFm ? options.threshold_sweep : options.fraction_sweep;
    MethodSummary m;
    m.parameter = free_parameter(methods[k]);
    m.static_background = summarise(episodes, k, sweep, options, "static");
    m.moving_background = summarise(episodes, k, sweep, options, "moving");
    m.all = summarise(episodes, k, sweep, options);
    for (const auto& o : objects) {
      m.by_object[o.empty() ? "(none)" : o] = summarise(episodes, k, sweep, options, kAnyGroup, o);
    }
    for (const auto& sc : scenarios) {
      m.by_scenario[sc.empty() ? "(none)" : sc] =
          summarise(episodes, k, sweep, options, kAnyGroup, kAnyGroup, sc);
    }
    summaries.push_back(&(out.methods[to_string(methods[k])] = std::move(m)));
  }
  for (std::size_t a = 0; a < methods.size(); ++a) {
    for (std::size_t b = a + 1; b < methods.size(); ++b) {
      const MethodSummary& ma = *summaries[a];
      const MethodSummary& mb = *summaries[b];
      KsComparison& ks = out.ks[to_string(methods[a]) + "_vs_" + to_string(methods[b])];
      ks.all = ks_two_sample(ma.all.jaccards, mb.all.jaccards);
      ks.static_background =
          ks_two_sample(ma.static_background.jaccards, mb.static_background.jaccards);
      ks.moving_background =
          ks_two_sample(ma.moving_background.jaccards, mb.moving_background.jaccards);
    }
  }
  out.episodes = episodes.size();
  return out;
}

std::string episodes_csv(const std::vector<EpisodeEvaluation>& episodes) {
  std::string out =
      core::join_csv_line({"episode", "scenario", "object", "background", "method", "status",
                           "scored_frame", "precision", "recall", "jaccard", "tanimoto", "l2",
                           "all_frames_jaccard", "all_frames_count", "seconds", "message"});
  out += '\n';
  for (const auto& e : episodes) {
    for (const auto& o : e.outcomes) {
      const bool ok = o.status == "ok";
      out += core::join_csv_line(
          {csv_text(e.name), csv_text(e.scenario), csv_text(e.object), e.background,
           to_string(o.method), o.status, std::to_string(o.scored_frame),
           ok ? fmt(o.metrics.precision) : "", ok ? fmt(o.metrics.recall) : "",
           ok ? fmt(o.metrics.jaccard) : "", ok ? fmt(o.metrics.tanimoto()) : "",
           ok ? fmt(o.metrics.l2) : "", o.all_frames_jaccard ? fmt(*o.all_frames_jaccard) : "",
           std::to_string(o.all_frames_count), fmt(o.seconds), csv_text(o.message)});
      out += '\n';
    }
  }
  return out;
}

}  // namespace proprio::eval

// Self-supervision against the simulator's ground truth, and its held-out views.
#include "proprio/loop/self_supervision_scoring.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <map>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <set>
#include <utility>

#include "proprio/core/error.hpp"
#include "proprio/core/random.hpp"
#include "proprio/core/text.hpp"
#include "proprio/episode/episode.hpp"
#include "proprio/features/extraction.hpp"
#include "proprio/features/mask_morphology.hpp"
#include "proprio/loop/push_run.hpp"
#include "proprio/loop/view_model.hpp"
#include "proprio/recognition/mot.hpp"
#include "proprio/recognition/topic_mapping.hpp"
#include "proprio/topics/corpus.hpp"
#include "proprio/topics/inference.hpp"

namespace proprio::loop {

core::Json held_out_confusion_json(const recognition::ConfusionMatrix& m, double accuracy) {
  core::Json j = m.to_json();
  j["accuracy"] = accuracy;
  j.erase("mean_class_accuracy");
  return j;
}

Eigen::MatrixXd weighted_word_multinomials(const topics::Corpus& corpus,
                                           std::span<const int> labels, int classes,
                                           std::span<const double> weights) {
  if (weights.empty()) return topics::fit_word_multinomials(corpus, labels, classes, 1.0);
  const std::size_t n = corpus.num_documents();
  if (labels.size() != n || weights.size() != n) {
    throw Error(core::cat({"weighted_word_multinomials: ", std::to_string(n), " documents, ",
                           std::to_string(labels.size()), " labels, ",
                           std::to_string(weights.size()), " weights"}));
  }
  if (classes < 1) throw Error("weighted_word_multinomials: classes must be >= 1");
  Eigen::MatrixXd counts = Eigen::MatrixXd::Ones(classes, corpus.num_words());  // add-one
  for (std::size_t d = 0; d < n; ++d) {
    if (!std::isfinite(weights[d]) || weights[d] < 0) {
      throw Error(core::cat({"weighted_word_multinomials: weight of document ", std::to_string(d),
                             " is negative or not finite"}));
    }
    if (labels[d] >= classes) {
      throw Error(core::cat({"weighted_word_multinomials: label ", std::to_string(labels[d]),
                             " of document ", std::to_string(d), " >= classes"}));
    }
    if (labels[d] < 0) continue;
    const topics::DocumentView doc = corpus.document(d);
    for (std::size_t i = 0; i < doc.size(); ++i)
      counts(labels[d], doc.words[i]) += weights[d] * doc.counts[i];
  }
  for (Eigen::Index c = 0; c < counts.rows(); ++c) {
    counts.row(c) = (counts.row(c) / counts.row(c).sum()).array().log().matrix();
  }
  return counts;
}

std::vector<double> per_view_weights(const topics::Corpus& corpus, std::span<const int> labels) {
  const std::size_t n = corpus.num_documents();
  if (labels.size() != n) {
    throw Error(core::cat({"per_view_weights: ", std::to_string(n), " documents but ",
                           std::to_string(labels.size()), " labels"}));
  }
  std::vector<double> words(n, 0.0);
  double total = 0;
  int labelled = 0;
  for (std::size_t d = 0; d < n; ++d) {
    const topics::DocumentView doc = corpus.document(d);
    for (std::size_t i = 0; i < doc.size(); ++i) words[d] += doc.counts[i];
    if (labels[d] >= 0 && words[d] > 0) {
      total += words[d];
      ++labelled;
    }
  }
  const double mean = labelled > 0 ? total / labelled : 0.0;
  std::vector<double> w(n, 0.0);
  for (std::size_t d = 0; d < n; ++d) {
    if (labels[d] >= 0 && words[d] > 0) w[d] = mean / words[d];
  }
  return w;
}

std::string pushed_most(std::span<const PushTruth> pushes,
                        const std::function<bool(int round)>& in_round) {
  // Ties were once broken by name alone: a class whose three pushes went to three objects was
  // named after the alphabetically first, whatever its views showed (session 33's trace).
  std::map<std::string, std::pair<int, int>> counts;  // name -> (pushes aimed, views shown)
  for (const PushTruth& p : pushes) {
    if (p.phase != "learn" || !in_round(p.round)) continue;
    if (p.executed && !p.intended.empty()) ++counts[p.intended].first;
    if (!p.view_truth.empty()) counts[p.view_truth].second += p.views;
  }
  std::string most;
  std::pair<int, int> best{0, 0};
  for (const auto& [name, n] : counts) {
    if (n.first > 0 && n > best) {  // lexicographic: pushes, then views; the map is by name
      best = n;
      most = name;
    }
  }
  return most;
}

topics::Corpus words_from(const topics::Corpus& corpus, int first) {
  if (first < 0 || first >= corpus.num_words()) {
    throw Error(core::cat({"words_from: word ", std::to_string(first), " is not in [0, ",
                           std::to_string(corpus.num_words()), ")"}));
  }
  topics::Corpus out(corpus.num_words() - first);
  std::vector<std::int32_t> ids;
  std::vector<std::int32_t> counts;
  for (std::size_t d = 0; d < corpus.num_documents(); ++d) {
    const topics::DocumentView doc = corpus.document(d);
    ids.clear();
    counts.clear();
    for (std::size_t i = 0; i < doc.size(); ++i) {
      if (doc.words[i] < first) continue;
      ids.push_back(doc.words[i] - first);
      counts.push_back(doc.counts[i]);
    }
    out.add_document(ids, counts);
  }
  return out;
}

Eigen::MatrixXd colour_multinomials(const topics::Corpus& training, std::span<const int> labels,
                                    int classes, int colour_from) {
  const topics::Corpus c = words_from(training, colour_from);
  return weighted_word_multinomials(c, labels, classes, per_view_weights(c, labels));
}

topics::MotClassification classify_by_colour(const topics::MotModel& model,
                                             const Eigen::MatrixXd& log_colour,
                                             const topics::Corpus& held, int colour_from) {
  const topics::Corpus colours = words_from(held, colour_from);
  // At weight 1 pool_word_multinomials scores log p(c) + sum_n log p(w_n | c): the MoT's term
  // (by_words less the prior) is weighed by 0. Rows of the prior make that term exactly 0.
  topics::MotClassification prior;
  prior.log_score = model.log_prior().transpose().replicate(
      static_cast<Eigen::Index>(colours.num_documents()), 1);
  return topics::pool_word_multinomials(model, prior, log_colour, colours, 1.0);
}

std::vector<double> counts_once(std::span<const int> labels, std::span<const int> push) {
  if (labels.size() != push.size()) {
    throw Error(core::cat({"counts_once: ", std::to_string(labels.size()), " labels but ",
                           std::to_string(push.size()), " pushes"}));
  }
  std::map<std::pair<int, int>, int> views;
  for (std::size_t i = 0; i < labels.size(); ++i) ++views[{labels[i], push[i]}];
  std::vector<double> w(labels.size());
  for (std::size_t i = 0; i < labels.size(); ++i) w[i] = 1.0 / views[{labels[i], push[i]}];
  return w;
}

namespace {

// The pooled words classifier's held-out figure: `model` (classes named by `right`'s test) with
// the word multinomials `log_phi`, on the held-out words of each object (`held`, whose MoT-by-words
// scores are `by_words`); `right(c, oi)`: class c is held-out object oi's.
template <class Right>
PooledFigure pooled_figure(const topics::MotModel& model, const Eigen::MatrixXd& log_phi,
                           const std::vector<topics::Corpus>& held,
                           const std::vector<topics::MotClassification>& by_words, double weight,
                           bool once, const Right& right) {
  PooledFigure f;
  f.weight = weight;
  f.once = once;
  f.per_object.assign(held.size(), 0.0);
  int ok_all = 0;
  int n = 0;
  for (std::size_t oi = 0; oi < held.size(); ++oi) {
    const auto docs = static_cast<int>(held[oi].num_documents());
    if (docs == 0) continue;
    const topics::MotClassification cls =
        topics::pool_word_multinomials(model, by_words[oi], log_phi, held[oi], weight);
    int ok = 0;
    for (const int c : cls.predicted) {
      if (c >= 0 && right(c, oi)) ++ok;
    }
    f.per_object[oi] = static_cast<double>(ok) / docs;
    ok_all += ok;
    n += docs;
  }
  f.accuracy = n > 0 ? static_cast<double>(ok_all) / n : 0.0;
  return f;
}

// MoT-by-words scores of each object's held-out words (empty for an object with none).
std::vector<topics::MotClassification> by_words_of(const topics::MotModel& model,
                                                   const topics::LdaModel& lda,
                                                   const std::vector<topics::Corpus>& held) {
  std::vector<topics::MotClassification> w(held.size());
  for (std::size_t oi = 0; oi < held.size(); ++oi) {
    if (held[oi].num_documents() > 0) w[oi] = topics::classify_mot_words(model, lda, held[oi]);
  }
  return w;
}

// The table point the held-out views put an object at: the middle of the scatter region.
const Eigen::Vector2d kHeldOutCentre{0.27, 0.0};
constexpr int kScatterAttempts = 10;
constexpr std::uint64_t kRescatterStream = 0x73636174746572ULL;  // core::stream_seed key

double fraction(int a, int b) { return b > 0 ? static_cast<double>(a) / b : 0.0; }

// The id with the most votes (the lowest among ties, as the map is ordered) and its votes;
// {0, 0} when none.
std::pair<int, int> most_voted(const std::map<int, int>& votes) {
  int best = 0;
  int best_n = 0;
  for (const auto& [id, n] : votes) {
    if (n > best_n) {
      best = id;
      best_n = n;
    }
  }
  return {best, best_n};
}

// A blob's votes (ground-truth id -> points) as "name:share+name:share", largest first
// (PushTruth::blob_truth); "" when no point lies on an object.
std::string blob_composition(const std::map<int, int>& votes,
                             const std::vector<sim::ObjectTruth>& objects) {
  int all = 0;
  for (const auto& [id, n] : votes) all += n;
  if (all == 0) return {};
  std::vector<std::pair<int, int>> byn(votes.begin(), votes.end());
  std::stable_sort(byn.begin(), byn.end(),
                   [](const auto& a, const auto& b) { return a.second > b.second; });
  std::string out;
  for (const auto& [id, n] : byn) {
    std::string name = "?";
    for (const auto& o : objects) {
      if (o.id == id) name = o.name;
    }
    if (!out.empty()) out += '+';
    out += core::printf_string("%s:%.2f", name.c_str(), static_cast<double>(n) / all);
  }
  return out;
}

constexpr std::uint64_t kLadderStream = 0x6c6164646572ULL;  // core::stream_seed key: a0_table
constexpr int kLadderRenders = 24;                          // a0, a0_table: views per object

// The classes named in `labels` ("" rows left out; a name with < 2 views has no class), sorted,
// and each row's class (-1: none).
std::pair<std::vector<std::string>, std::vector<int>> label_classes(
    const std::vector<std::string>& labels) {
  std::map<std::string, int> count;
  for (const auto& l : labels) {
    if (!l.empty()) ++count[l];
  }
  std::vector<std::string> classes;
  for (const auto& [l, n] : count) {
    if (n >= 2) classes.push_back(l);
  }
  std::vector<int> ids(labels.size(), -1);
  for (std::size_t i = 0; i < labels.size(); ++i) {
    const auto it = std::find(classes.begin(), classes.end(), labels[i]);
    if (it != classes.end()) ids[i] = static_cast<int>(it - classes.begin());
  }
  return {classes, ids};
}

// An own-model rung (SelfSupervisionOptions::own_model_rungs): the views `descriptors` labelled
// by `labels` (as ladder_rung's) through a vocabulary and an LDA model built from the labelled
// views' own descriptors (views_vocabulary, views_lda), a supervised Mixture of Topics on their
// theta and per-view word multinomials; each object's held-out descriptors (`held`) in the same
// vocabulary, classified by the pooled words classifier. `accuracy` and `per_object` at
// options.mot_word_weight, `pooled` at every kPooledWeights. `right(class name, oi)`: the class
// is held-out object oi's.
template <class Right>
LadderRung own_rung(std::string name, std::string what, const std::vector<cv::Mat>& descriptors,
                    const std::vector<std::string>& labels,
                    const std::vector<std::vector<cv::Mat>>& held,
                    const SelfSupervisionOptions& options, const Right& right) {
  LadderRung r;
  r.name = std::move(name);
  r.what = std::move(what);
  r.per_object.assign(held.size(), 0.0);
  if (descriptors.size() != labels.size()) {
    throw Error(core::cat({"own-model rung ", r.name, ": ", std::to_string(descriptors.size()),
                           " views' descriptors for ", std::to_string(labels.size()), " labels"}));
  }
  const auto labelled = label_classes(labels);
  const std::vector<std::string>& classes = labelled.first;
  const std::vector<int>& all_ids = labelled.second;
  r.classes = static_cast<int>(classes.size());
  std::vector<cv::Mat> views;
  std::vector<int> ids;
  for (std::size_t i = 0; i < labels.size(); ++i) {
    if (all_ids[i] < 0) continue;
    views.push_back(descriptors[i]);
    ids.push_back(all_ids[i]);
  }
  r.training_views = static_cast<int>(views.size());
  if (classes.empty()) return r;
  const features::Vocabulary vocabulary = views_vocabulary(views, options.own_words, options.seed);
  topics::Corpus corpus(vocabulary.size());
  for (const cv::Mat& v : views) corpus.add_tokens(features::bag_of_words(vocabulary, v));
  const topics::LdaModel lda = views_lda(corpus, options.own_topics, options.seed);
  topics::MotModel model;
  try {
    model =
        topics::fit_mot(recognition::document_theta(lda, corpus).theta, ids, classes, options.mot)
            .model;
  } catch (const Error& e) {
    r.what += core::cat({" (fit failed: ", e.what(), ")"});
    r.accuracy = -1;
    return r;
  }
  const Eigen::MatrixXd log_phi = weighted_word_multinomials(
      corpus, ids, static_cast<int>(classes.size()), per_view_weights(corpus, ids));
  std::vector<topics::Corpus> held_words(held.size(), topics::Corpus(vocabulary.size()));
  for (std::size_t oi = 0; oi < held.size(); ++oi) {
    for (const cv::Mat& h : held[oi])
      held_words[oi].add_tokens(features::bag_of_words(vocabulary, h));
  }
  const auto by_words = by_words_of(model, lda, held_words);
  const auto is_right = [&](int c, std::size_t oi) {
    return right(classes[static_cast<std::size_t>(c)], oi);
  };
  const PooledFigure f =
      pooled_figure(model, log_phi, held_words, by_words, options.mot_word_weight, false, is_right);
  r.accuracy = f.accuracy;
  r.per_object = f.per_object;
  r.pooled.emplace();
  for (const double w : kPooledWeights) {
    r.pooled->push_back(pooled_figure(model, log_phi, held_words, by_words, w, false, is_right));
  }
  return r;
}

// A rung of the oracle ladder: a supervised Mixture of Topics over the classes named in `labels`
// ("" rows left out; a name with < 2 views has no class), scored on `held` (per object of
// `objects`: its held-out views' theta) by the rule of the printouts: right when the class
// given is the view's own object.
LadderRung ladder_rung(std::string name, std::string what, const Eigen::MatrixXd& theta,
                       const std::vector<std::string>& labels,
                       const std::vector<std::string>& objects,
                       const std::vector<Eigen::MatrixXd>& held, const topics::MotOptions& mot,
                       const topics::Corpus* words = nullptr,
                       const std::vector<topics::Corpus>* held_words = nullptr,
                       const topics::LdaModel* lda = nullptr) {
  LadderRung r;
  r.name = std::move(name);
  r.what = std::move(what);
  r.per_object.assign(objects.size(), 0.0);
  const auto labelled = label_classes(labels);
  const std::vector<std::string>& classes = labelled.first;
  const std::vector<int>& ids = labelled.second;
  for (const int id : ids) r.training_views += id >= 0 ? 1 : 0;
  r.classes = static_cast<int>(classes.size());
  if (classes.empty()) return r;
  topics::MotModel model;
  try {
    model = topics::fit_mot(theta, ids, classes, mot).model;
  } catch (const Error& e) {
    r.what += core::cat({" (fit failed: ", e.what(), ")"});
    r.accuracy = -1;
    return r;
  }
  int right = 0;
  int n = 0;
  for (std::size_t oi = 0; oi < objects.size() && oi < held.size(); ++oi) {
    if (held[oi].rows() == 0) continue;
    const topics::MotClassification cls = topics::classify_mot(model, held[oi]);
    int ok = 0;
    for (const int c : cls.predicted) {
      if (c >= 0 && classes[static_cast<std::size_t>(c)] == objects[oi]) ++ok;
    }
    r.per_object[oi] = fraction(ok, static_cast<int>(held[oi].rows()));
    right += ok;
    n += static_cast<int>(held[oi].rows());
  }
  r.accuracy = fraction(right, n);
  if (words != nullptr && held_words != nullptr && lda != nullptr) {
    // The same views' words (rows of theta), the same classes: the pooled words classifier.
    const Eigen::MatrixXd log_phi =
        weighted_word_multinomials(*words, ids, static_cast<int>(classes.size()));
    const auto by_words = by_words_of(model, *lda, *held_words);
    const auto is_right = [&](int c, std::size_t oi) {
      return classes[static_cast<std::size_t>(c)] == objects[oi];
    };
    r.pooled.emplace();
    for (const double w : kPooledWeights) {
      r.pooled->push_back(pooled_figure(model, log_phi, *held_words, by_words, w, false, is_right));
    }
  }
  return r;
}

}  // namespace

GroundTruthAttendant::GroundTruthAttendant(sim::SimulatedRobot& robot, std::uint64_t seed)
    : robot_(robot), seed_(seed) {}

RoundTruth& GroundTruthAttendant::round(int r) {
  if (static_cast<int>(rounds_.size()) <= r) rounds_.resize(static_cast<std::size_t>(r) + 1);
  return rounds_[static_cast<std::size_t>(r)];
}

std::string GroundTruthAttendant::rescatter(int round) {
  // As SimulatedRobot::scatter, but a draw that found no room for an object (it leaves the
  // object at the arm's base, which blows the simulation up) is drawn again with the next seed.
  const sim::ObjectCatalogue catalogue = sim::ObjectCatalogue::load_default();
  std::vector<const sim::ObjectType*> types;
  // The distractors slide about behind the work area (a moving backdrop): a person re-scatters
  // what is on the table, objects and clutter.
  for (const auto& o : robot_.ground_truth()) {
    if (o.role != sim::TableRole::kDistractor) types.push_back(&catalogue.get(o.name));
  }
  const sim::ScatterRegion region;
  std::uint64_t s = 0;
  std::vector<sim::Placement> places;
  for (int attempt = 0; attempt < kScatterAttempts; ++attempt) {
    s = core::stream_seed(seed_, kRescatterStream, static_cast<std::uint64_t>(round),
                          static_cast<std::uint64_t>(attempt));
    places = sim::scatter_placements(types, region, s);
    const bool ok = std::all_of(places.begin(), places.end(), [&](const sim::Placement& p) {
      return std::isfinite(p.position.x()) && std::isfinite(p.position.y()) &&
             p.position.norm() >= region.base_clearance;
    });
    if (ok) break;
    spdlog::warn("re-scatter (seed {}): no room for every object; drawing again", s);
  }
  robot_.place(places);
  std::string line = core::cat({"re-scattered (seed ", std::to_string(s), "):"});
  for (const auto& p : places) {
    line += core::printf_string(" %s (%.3f, %.3f) m yaw %.2f;", p.name.c_str(), p.position.x(),
                                p.position.y(), p.yaw);
  }
  return line;
}

std::map<int, int> GroundTruthAttendant::votes_under(const planning::PutativeObject& blob) {
  const cv::Mat mask = robot_.ground_truth_mask();
  std::map<int, int> votes;
  for (const auto& p : blob.pixels) {
    const int u = static_cast<int>(std::lround(p.x()));
    const int v = static_cast<int>(std::lround(p.y()));
    if (u < 0 || v < 0 || u >= mask.cols || v >= mask.rows) continue;
    const int id = mask.at<std::uint16_t>(v, u);
    if (id != 0) ++votes[id];
  }
  return votes;
}

std::string GroundTruthAttendant::object_under(const planning::PutativeObject& blob) {
  const int best = most_voted(votes_under(blob)).first;
  for (const auto& o : robot_.ground_truth()) {
    if (o.id == best) return o.name;
  }
  return {};
}

void GroundTruthAttendant::chose(int r, const planning::PlanningView& view, int blob) {
  round(r).chosen = object_under(view.objects.at(static_cast<std::size_t>(blob)));
  round(r).blobs.clear();
  for (const auto& o : view.objects) round(r).blobs.push_back(object_under(o));
}

void GroundTruthAttendant::before_push(const PushIntent& intent) {
  before_ = robot_.ground_truth();
  PushTruth t;
  t.round = intent.round;
  t.phase = intent.phase;
  const auto& blob = intent.view->objects.at(static_cast<std::size_t>(intent.blob));
  t.intended = object_under(blob);
  t.blob_truth = blob_composition(votes_under(blob), before_);
  for (const auto& o : before_) {
    if (o.name == t.intended && !o.upright) t.lying_before = true;
  }
  pushes_.push_back(t);
  if (intent.phase == "learn") {
    for (const auto& o : before_) {
      if (o.name == round(intent.round).chosen) round(intent.round).yaws.push_back(o.yaw);
    }
  }
}

void GroundTruthAttendant::after_push(const PushIntent& intent, bool executed) {
  PushTruth& t = pushes_.back();
  t.executed = executed;
  const std::vector<sim::ObjectTruth> after = robot_.ground_truth();
  bool intended_moved = false;
  for (std::size_t i = 0; i < after.size() && i < before_.size(); ++i) {
    if (after[i].role == sim::TableRole::kDistractor) continue;  // they always move
    if ((after[i].centre - before_[i].centre).head<2>().norm() > kMovedThreshold) {
      t.moved.push_back(after[i].name);
      if (after[i].name == t.intended) intended_moved = true;
    }
    if (before_[i].on_table && !after[i].on_table) ++t.fell_off;
    if (before_[i].upright && !after[i].upright) t.tipped.push_back(after[i].name);
    if (after[i].name == t.intended && before_[i].on_table && after[i].on_table) {
      t.turn_deg = turn_deg(before_[i].yaw, after[i].yaw);
    }
    if (intent.phase == "learn" && after[i].name == round(intent.round).chosen) {
      round(intent.round).yaws.push_back(after[i].yaw);
    }
  }
  t.only_intended = intended_moved && t.moved.size() == 1;
}

void GroundTruthAttendant::cleared(int r, const planning::PlanningView& view, int blob) {
  RoundTruth& rt = round(r);
  if (blob < 0) return;
  const std::string now = object_under(view.objects.at(static_cast<std::size_t>(blob)));
  const std::vector<sim::ObjectTruth> truth = robot_.ground_truth();
  const auto it = std::find_if(truth.begin(), truth.end(),
                               [&](const sim::ObjectTruth& o) { return o.name == now; });
  if (it == truth.end()) return;
  double gap = 1e9;
  for (const auto& o : truth) {
    if (o.name != now && o.on_table && o.role != sim::TableRole::kDistractor) {
      gap = std::min(gap, footprint_gap(*it, o));
    }
  }
  rt.least_gap = gap >= 1e9 ? 1.0 : gap;
  rt.singulated = now == rt.chosen && rt.least_gap >= 0.10;
}

void GroundTruthAttendant::views_taken(const PushIntent& /*intent*/, int views,
                                       const cv::Mat& last_mask) {
  PushTruth& t = pushes_.back();
  t.views = views;
  if (last_mask.empty()) return;
  const cv::Mat ids = robot_.ground_truth_mask();
  std::map<int, int> votes;
  for (int v = 0; v < ids.rows; ++v) {
    for (int u = 0; u < ids.cols; ++u) {
      if (last_mask.at<std::uint8_t>(v, u) == 0) continue;
      const int id = ids.at<std::uint16_t>(v, u);
      if (id != 0 && id != sim::kArmId) ++votes[id];
    }
  }
  const int best = most_voted(votes).first;
  for (const auto& o : robot_.ground_truth()) {
    if (o.id == best) t.view_truth = o.name;
  }
}

void GroundTruthAttendant::view_taken(const PushIntent& intent,
                                      const std::filesystem::path& episode, int frame,
                                      const cv::Mat& mask) {
  ViewTruth t;
  t.round = intent.round;
  t.episode = episode;
  t.frame = frame;
  t.intended = pushes_.empty() ? std::string() : pushes_.back().intended;
  for (const auto& o : robot_.ground_truth()) {
    if (o.name != t.intended || !o.on_table) continue;
    t.posed = true;
    t.position = o.position.head<2>();
    t.yaw = o.yaw;
    t.upright = o.upright;
  }
  // The ground-truth ids of the view: the episode's mask of that frame (recorded only with
  // TableOptions::record_masks), or the table now (the look after the push).
  cv::Mat ids;
  std::map<int, std::string> names;
  if (episode.empty()) {
    ids = robot_.ground_truth_mask();
    for (const auto& o : robot_.ground_truth()) names[o.id] = o.name;
  } else {
    if (!episode_ || episode_->dir() != episode) {
      episode_.reset();
      episode_.emplace(episode::read_episode(episode));
    }
    if (episode_->info().has_masks && frame >= 0 && frame < episode_->frame_count()) {
      ids = episode_->mask(frame);
      for (const auto& o : episode_->objects()) names[o.id] = o.name;
    }
  }
  if (!ids.empty() && ids.size() == mask.size()) {
    t.known = true;
    std::map<int, int> votes;
    int all = 0;
    int arm = 0;
    int background = 0;
    for (int v = 0; v < ids.rows; ++v) {
      for (int u = 0; u < ids.cols; ++u) {
        if (mask.at<std::uint8_t>(v, u) == 0) continue;
        ++all;
        const int id = ids.at<std::uint16_t>(v, u);
        if (id == 0) {
          ++background;
        } else if (id == sim::kArmId) {
          ++arm;
        } else {
          ++votes[id];
        }
      }
    }
    const auto [best, best_n] = most_voted(votes);
    if (best != 0) t.object = names[best];
    t.share_object = fraction(best_n, all);
    t.share_arm = fraction(arm, all);
    t.share_background = fraction(background, all);
  }
  views_.push_back(std::move(t));
}

double footprint_gap(const sim::ObjectTruth& a, const sim::ObjectTruth& b) {
  const double d = (a.centre - b.centre).head<2>().norm() - a.footprint_radius - b.footprint_radius;
  return std::max(0.0, d);
}

double turn_deg(double a, double b) {
  constexpr double kTwoPi = 2 * std::numbers::pi;
  double d = std::fmod(std::abs(b - a), kTwoPi);
  if (d > std::numbers::pi) d = kTwoPi - d;
  return d * 180.0 / std::numbers::pi;
}

double yaw_coverage_deg(std::vector<double> yaws) {
  if (yaws.size() < 2) return 0;
  constexpr double kTwoPi = 2 * std::numbers::pi;
  for (double& y : yaws) y = std::fmod(std::fmod(y, kTwoPi) + kTwoPi, kTwoPi);
  std::sort(yaws.begin(), yaws.end());
  double largest = kTwoPi - yaws.back() + yaws.front();
  for (std::size_t i = 1; i < yaws.size(); ++i) largest = std::max(largest, yaws[i] - yaws[i - 1]);
  return (kTwoPi - largest) * 180.0 / std::numbers::pi;
}

namespace {

// The id an episode's masks give the object named `name` (its last listing; -1: not among its
// objects).
int object_id(const episode::Episode& e, const std::string& name) {
  int id = -1;
  for (const auto& o : e.objects()) {
    if (o.name == name) id = o.id;
  }
  return id;
}

// The ladder's probes (SelfSupervisionOptions::ladder_probes): each push's last frame against a
// clean render of the same pose, with one thing changed at a time (OracleLadder::probe_names).
struct Probes {
  std::vector<std::string> names;
  std::vector<std::string> whats;
  std::vector<topics::Corpus> corpora;
  std::vector<std::vector<std::string>> labels;
  std::map<std::string, double> sum;
  std::map<std::string, int> count;
  Probes(std::size_t words, std::initializer_list<std::pair<const char*, const char*>> rungs) {
    for (const auto& [n, w] : rungs) {
      names.emplace_back(n);
      whats.emplace_back(w);
      corpora.emplace_back(words);
      labels.emplace_back();
    }
  }
  void add(std::size_t k, const std::vector<std::int32_t>& doc, const std::string& label) {
    corpora[k].add_tokens(doc);
    labels[k].push_back(label);
  }
  void stat(const std::string& object, const std::string& key, double value) {
    for (std::string name : {object, std::string("all")}) {
      name += '.';
      name += key;
      sum[name] += value;
      ++count[name];
    }
  }
};

// What lies under each feature's support window (the dense SIFT patch, `side` px square) in a
// ground-truth id image: bit 0 the arm, bit 1 another object, bit 2 the background.
int window_content(const cv::Mat& ids, int id, const cv::KeyPoint& k, float side) {
  const int half = static_cast<int>(std::ceil(side / 2));
  const int cx = static_cast<int>(std::lround(k.pt.x));
  const int cy = static_cast<int>(std::lround(k.pt.y));
  int bits = 0;
  for (int y = std::max(0, cy - half); y < std::min(ids.rows, cy + half); ++y) {
    for (int x = std::max(0, cx - half); x < std::min(ids.cols, cx + half); ++x) {
      const int v = ids.at<std::uint16_t>(y, x);
      if (v == sim::kArmId) {
        bits |= 1;
      } else if (v == 0) {
        bits |= 4;
      } else if (v != id) {
        bits |= 2;
      }
    }
  }
  return bits;
}

// The words of the features of `f` in `rows` (none when `rows` is empty).
std::vector<std::int32_t> words_of(const features::Vocabulary& vocabulary,
                                   const features::Features& f, const std::vector<int>& rows) {
  if (rows.empty()) return {};
  return features::bag_of_words(vocabulary, features::select_features(f, rows).descriptors);
}

void probe_push_view(Probes& p, const std::string& name, int frame_id, const cv::Mat& frame,
                     const cv::Mat& frame_ids, const cv::Mat& render, const cv::Mat& render_mask,
                     const features::Vocabulary& vocabulary, const SelfSupervisionOptions& o) {
  const cv::Mat mg = frame_ids == frame_id;
  const cv::Mat& mr = render_mask;
  const cv::Mat arm = frame_ids == sim::kArmId;
  const cv::Mat other = (frame_ids != frame_id) & (frame_ids != 0) & (frame_ids != sim::kArmId);
  const int min = o.min_features;
  const auto doc = [&](const cv::Mat& image, const cv::Mat& mask, int dilate) {
    return masked_document(image, mask, vocabulary, o.features, dilate);
  };
  const auto put = [&](std::size_t k, const std::vector<std::int32_t>& d) {
    if (static_cast<int>(d.size()) >= min) p.add(k, d, name);
  };
  // Pixel statistics: the pose's agreement, the object's own pixels, the table round it.
  const double inter = cv::countNonZero(mg & mr);
  const double uni = cv::countNonZero(mg | mr);
  p.stat(name, "iou", uni > 0 ? inter / uni : 0);
  p.stat(name, "frame_object_px", cv::countNonZero(mg));
  p.stat(name, "render_object_px", cv::countNonZero(mr));
  const cv::Mat hidden = mr & ~mg;
  const double hidden_n = cv::countNonZero(hidden);
  p.stat(name, "render_px_hidden", cv::countNonZero(mr) > 0 ? hidden_n / cv::countNonZero(mr) : 0);
  p.stat(name, "hidden_by_arm", hidden_n > 0 ? cv::countNonZero(hidden & arm) / hidden_n : 0);
  p.stat(name, "hidden_by_other", hidden_n > 0 ? cv::countNonZero(hidden & other) / hidden_n : 0);
  cv::Mat gf;
  cv::Mat gr;
  cv::cvtColor(frame, gf, cv::COLOR_BGR2GRAY);
  cv::cvtColor(render, gr, cv::COLOR_BGR2GRAY);
  cv::Mat diff;
  cv::absdiff(gf, gr, diff);
  cv::Mat core_both;
  cv::erode(mg & mr, core_both, cv::Mat(), {-1, -1}, 2);
  if (cv::countNonZero(core_both) > 0)
    p.stat(name, "grey_diff_object", cv::mean(diff, core_both)[0]);
  const cv::Mat band =
      features::dilated(mg | mr, 12) & ~features::dilated(mg | mr, 2) & (frame_ids == 0);
  if (cv::countNonZero(band) > 0) p.stat(name, "grey_diff_table_band", cv::mean(diff, band)[0]);
  // Features: what their windows reach, and their words against the render's at the same points.
  const cv::Mat fm = features::dilated(mg, o.dilate);
  const cv::Mat rm = features::dilated(mr, o.dilate);
  const features::Features ff = features::extract_features(frame, o.features, fm);
  const features::Features fr = features::extract_features(render, o.features, rm);
  const std::vector<std::int32_t> wf = ff.size() > 0
                                           ? features::bag_of_words(vocabulary, ff.descriptors)
                                           : std::vector<std::int32_t>{};
  const std::vector<std::int32_t> wr = fr.size() > 0
                                           ? features::bag_of_words(vocabulary, fr.descriptors)
                                           : std::vector<std::int32_t>{};
  p.stat(name, "frame_features", ff.size());
  p.stat(name, "render_features", fr.size());
  const float side = o.features.dense.size;
  cv::Mat render_ids(render_mask.size(), CV_16U, cv::Scalar(0));
  render_ids.setTo(frame_id, mr);
  std::map<std::pair<int, int>, std::int32_t> render_word;
  int render_touch_bg = 0;
  for (int i = 0; i < fr.size(); ++i) {
    const cv::KeyPoint& k = fr.keypoints[static_cast<std::size_t>(i)];
    render_word[{static_cast<int>(std::lround(k.pt.x)), static_cast<int>(std::lround(k.pt.y))}] =
        wr[static_cast<std::size_t>(i)];
    if ((window_content(render_ids, frame_id, k, side) & 4) != 0) ++render_touch_bg;
  }
  if (fr.size() > 0) p.stat(name, "render_feat_touch_table", double(render_touch_bg) / fr.size());
  int touch_arm = 0;
  int touch_other = 0;
  int touch_bg = 0;
  int inside = 0;
  int same_clean = 0;
  int both_clean = 0;
  int same_dirty = 0;
  int both_dirty = 0;
  std::vector<int> clean_rows;
  std::vector<int> no_arm_rows;
  for (int i = 0; i < ff.size(); ++i) {
    const cv::KeyPoint& k = ff.keypoints[static_cast<std::size_t>(i)];
    const int bits = window_content(frame_ids, frame_id, k, side);
    touch_arm += (bits & 1) != 0 ? 1 : 0;
    touch_other += (bits & 2) != 0 ? 1 : 0;
    touch_bg += (bits & 4) != 0 ? 1 : 0;
    inside += bits == 0 ? 1 : 0;
    const bool dirty = (bits & 3) != 0;
    if (!dirty) clean_rows.push_back(i);
    if ((bits & 1) == 0) no_arm_rows.push_back(i);
    const auto it = render_word.find(
        {static_cast<int>(std::lround(k.pt.x)), static_cast<int>(std::lround(k.pt.y))});
    if (it == render_word.end()) continue;
    const bool same = it->second == wf[static_cast<std::size_t>(i)];
    (dirty ? both_dirty : both_clean)++;
    if (same) (dirty ? same_dirty : same_clean)++;
  }
  if (ff.size() > 0) {
    p.stat(name, "frame_feat_touch_arm", double(touch_arm) / ff.size());
    p.stat(name, "frame_feat_touch_other", double(touch_other) / ff.size());
    p.stat(name, "frame_feat_touch_table", double(touch_bg) / ff.size());
    p.stat(name, "frame_feat_inside", double(inside) / ff.size());
  }
  if (both_clean > 0) p.stat(name, "same_word_clean", double(same_clean) / both_clean);
  if (both_dirty > 0) p.stat(name, "same_word_arm_or_other", double(same_dirty) / both_dirty);
  p.stat(name, "shared_points_clean", both_clean);
  p.stat(name, "shared_points_arm_or_other", both_dirty);
  // The probes' documents.
  put(0, wf);
  put(1, wr);
  put(2, doc(frame, mg, 0));
  put(3, doc(frame, mr, o.dilate));
  cv::Mat noarm = frame.clone();
  render.copyTo(noarm, arm);
  put(4, doc(noarm, mg, o.dilate));
  cv::Mat noother = frame.clone();
  render.copyTo(noother, other);
  put(5, doc(noother, mg, o.dilate));
  cv::Mat context = render.clone();
  frame.copyTo(context, mg);
  put(6, doc(context, mg, o.dilate));
  put(7, doc(context, mg | mr, o.dilate));
  put(8, words_of(vocabulary, ff, clean_rows));
  put(9, words_of(vocabulary, ff, no_arm_rows));
  cv::Mat swapped = frame.clone();
  render.copyTo(swapped, mr);
  put(10, doc(swapped, mr, o.dilate));
}

// SelfSupervisionOptions::own_model_rungs: the descriptors the own-model rungs need besides the
// robot's views' (TrainingViews::descriptors): a0's renders (rows of a0's corpus) and each
// object's held-out views (rows of its held-out corpus).
struct OwnDescriptors {
  std::vector<cv::Mat> a0;
  std::vector<std::vector<cv::Mat>> held;
};

// The rungs (a0, a0_table, a, b, b_pure, c_named, c; with own: a0_own, a_own, b_own, c_own); see
// OracleLadder.
OracleLadder oracle_ladder(
    const Learning& learning, const GroundTruthAttendant& attendant, const SelfSupervisionScore& s,
    const std::vector<std::string>& objects, const std::vector<Eigen::MatrixXd>& held,
    const topics::Corpus& a0, const std::vector<std::string>& a0_labels,
    const topics::Corpus& a0_table, const std::vector<std::string>& a0_table_labels,
    const topics::Corpus& alone, const std::vector<std::string>& alone_labels,
    const topics::LdaModel& model, const features::Vocabulary& vocabulary,
    const SelfSupervisionOptions& options, const std::vector<topics::Corpus>& held_words,
    const Probes* probes, const OwnDescriptors* own) {
  OracleLadder l;
  const bool pooled = options.pooled_score;
  const auto theta_of = [&](const topics::Corpus& c) {
    return c.num_documents() > 0 ? recognition::document_theta(model, c).theta
                                 : Eigen::MatrixXd(0, model.num_topics());
  };
  const auto rung = [&](std::string name, std::string what, const topics::Corpus& words,
                        const Eigen::MatrixXd& theta, const std::vector<std::string>& labels) {
    return ladder_rung(std::move(name), std::move(what), theta, labels, objects, held, options.mot,
                       pooled ? &words : nullptr, &held_words, &model);
  };
  l.rungs.push_back(rung("a0", "renders alone at the centre, other yaws; true labels", a0,
                         theta_of(a0), a0_labels));
  l.rungs.push_back(rung("a0_table",
                         "renders alone at random places and yaws of the table; true labels",
                         a0_table, theta_of(a0_table), a0_table_labels));
  // (a): the pushed object's ground-truth mask in the frames the learner took its views from.
  const std::vector<ViewTruth>& views = attendant.views();
  topics::Corpus a_corpus(vocabulary.size());
  std::vector<std::string> a_labels;
  topics::Corpus last_corpus(vocabulary.size());  // (a_last): each push's last view only
  std::vector<std::string> last_labels;
  std::vector<cv::Mat> a_descriptors;  // own: (a)'s views' descriptors
  std::vector<bool> a_upright;         // own: (a)'s views' object upright after its push
  std::optional<episode::Episode> e;
  for (std::size_t vi = 0; vi < views.size(); ++vi) {
    const ViewTruth& v = views[vi];
    if (v.episode.empty() || v.intended.empty() || v.frame < 0) continue;
    if (!e || e->dir() != v.episode) e.emplace(episode::read_episode(v.episode));
    if (!e->info().has_masks) continue;
    const int id = object_id(*e, v.intended);
    if (id < 0) continue;
    const cv::Mat ids = e->mask(v.frame);
    const cv::Mat mask = ids == id;
    // arm_patches_out: the patches reaching the arm's true pixels are left out.
    const cv::Mat arm = options.arm_patches_out ? cv::Mat(ids == sim::kArmId) : cv::Mat();
    cv::Mat desc =
        masked_descriptors(e->frame(v.frame), mask, options.features, options.dilate, arm);
    if (desc.rows < options.min_features) continue;
    const auto doc = features::bag_of_words(vocabulary, desc);
    a_corpus.add_tokens(doc);
    a_labels.push_back(v.intended);
    if (own != nullptr) {
      a_descriptors.push_back(std::move(desc));
      a_upright.push_back(v.posed && v.upright);
    }
    if (vi + 1 == views.size() || views[vi + 1].episode != v.episode) {
      last_corpus.add_tokens(doc);
      last_labels.push_back(v.intended);
    }
  }
  l.rungs.push_back(rung("a", "the pushed object's true mask in the push frames; true labels",
                         a_corpus, theta_of(a_corpus), a_labels));
  l.rungs.push_back(rung("a_last", "(a), each push's last view only (the arm lifted)", last_corpus,
                         theta_of(last_corpus), last_labels));
  l.rungs.push_back(rung("a_alone",
                         "renders of the object alone in the pose of each push's last view", alone,
                         theta_of(alone), alone_labels));
  if (probes != nullptr) {
    for (std::size_t k = 0; k < probes->names.size(); ++k) {
      l.rungs.push_back(rung(probes->names[k], probes->whats[k], probes->corpora[k],
                             theta_of(probes->corpora[k]), probes->labels[k]));
    }
    for (const auto& [key, total] : probes->sum) {
      l.probe_names.push_back(key);
      l.probe_values.push_back(total / probes->count.at(key));
    }
  }
  // (b), (c): the robot's own views (its masks), labelled by the truth or by the robot.
  const Eigen::MatrixXd& theta = learning.views.theta;
  const bool aligned = static_cast<Eigen::Index>(views.size()) == theta.rows();
  if (!aligned) {
    spdlog::warn("oracle ladder: {} view records for {} training views; (b) left out", views.size(),
                 theta.rows());
  }
  std::vector<std::string> b_labels(static_cast<std::size_t>(theta.rows()));
  std::vector<std::string> pure_labels(b_labels.size());
  std::vector<std::string> named(b_labels.size());
  int known = 0;
  int agree = 0;
  for (std::size_t i = 0; i < b_labels.size(); ++i) {
    const int c = learning.views.labels[i];
    named[i] = s.class_object[static_cast<std::size_t>(c)];
    if (!aligned || !views[i].known) continue;
    const ViewTruth& v = views[i];
    b_labels[i] = v.object;
    if (v.share_object >= 0.5) pure_labels[i] = v.object;
    ++known;
    if (!v.object.empty() && v.object == named[i]) ++agree;
    l.share_object += v.share_object;
    l.share_arm += v.share_arm;
    l.share_background += v.share_background;
    l.share_other += 1 - v.share_object - v.share_arm - v.share_background;
  }
  if (known > 0) {
    l.share_object /= known;
    l.share_arm /= known;
    l.share_background /= known;
    l.share_other /= known;
  }
  // The robot's views' words, when they are the rows of theta (not in a ceiling-only run).
  const bool have_words =
      static_cast<Eigen::Index>(learning.views.words.num_documents()) == theta.rows();
  const topics::Corpus& words = learning.views.words;
  const auto robot_rung = [&](std::string name, std::string what,
                              const std::vector<std::string>& labels) {
    return ladder_rung(std::move(name), std::move(what), theta, labels, objects, held, options.mot,
                       pooled && have_words ? &words : nullptr, &held_words, &model);
  };
  LadderRung b = robot_rung(
      "b", "the robot's views (its masks); true labels (object mostly in view)", b_labels);
  b.label_purity = 1;
  l.rungs.push_back(b);
  l.rungs.push_back(robot_rung(
      "b_pure", "(b), only views whose mask is at least half on the object", pure_labels));
  LadderRung cn = robot_rung(
      "c_named", "the robot's views and labels, classes named after one object merged", named);
  cn.label_purity = known > 0 ? static_cast<double>(agree) / known : -1;
  l.rungs.push_back(cn);
  LadderRung c;
  c.name = "c";
  c.what = "the robot's views and labels (today's figure)";
  c.training_views = static_cast<int>(theta.rows());
  c.classes = learning.model.num_classes();
  c.accuracy = s.mot_accuracy;
  c.label_purity = cn.label_purity;
  for (const ObjectScore& o : s.objects) c.per_object.push_back(o.mot_accuracy);
  c.pooled = s.pooled;
  l.rungs.push_back(c);
  if (own != nullptr) {
    // The same training views through a vocabulary and LDA model of their own (own_rung).
    const auto is_object = [&](const std::string& name, std::size_t oi) {
      return name == objects[oi];
    };
    l.rungs.push_back(own_rung("a0_own", "(a0) with a vocabulary and LDA of its own views", own->a0,
                               a0_labels, own->held, options, is_object));
    l.rungs.push_back(own_rung("a_own", "(a) with a vocabulary and LDA of its own views",
                               a_descriptors, a_labels, own->held, options, is_object));
    const std::vector<cv::Mat>& robot = learning.views.descriptors;
    if (aligned && robot.size() == b_labels.size()) {
      l.rungs.push_back(own_rung("b_own", "(b) with a vocabulary and LDA of its own views", robot,
                                 b_labels, own->held, options, is_object));
    }
    if (robot.size() == b_labels.size()) {
      // (c): the robot's classes (the learner's names), each right for the object it is named
      // after (SelfSupervisionScore::class_object).
      std::vector<std::string> classes(b_labels.size());
      for (std::size_t i = 0; i < classes.size(); ++i) {
        classes[i] = learning.class_names[static_cast<std::size_t>(learning.views.labels[i])];
      }
      const auto is_named = [&](const std::string& name, std::size_t oi) {
        for (std::size_t k = 0; k < learning.class_names.size(); ++k) {
          if (learning.class_names[k] == name) return s.class_object[k] == objects[oi];
        }
        return false;
      };
      LadderRung co = own_rung("c_own", "(c) with a vocabulary and LDA of its own views", robot,
                               classes, own->held, options, is_named);
      co.label_purity = cn.label_purity;
      l.rungs.push_back(co);
    } else {
      spdlog::warn(
          "oracle ladder: {} views' descriptors for {} training views; own rungs b, c "
          "left out",
          robot.size(), b_labels.size());
    }
    // (a) of the pushes that left their object standing only (ViewTruth::upright: after the
    // push), by the run's model and by an own one: what the toppled pushes cost.
    std::vector<std::string> up_labels(a_labels.size());
    for (std::size_t i = 0; i < up_labels.size(); ++i) {
      if (a_upright[i]) up_labels[i] = a_labels[i];
    }
    l.rungs.push_back(rung("a_up", "(a), only views whose object stood upright after its push",
                           a_corpus, theta_of(a_corpus), up_labels));
    l.rungs.push_back(own_rung("a_up_own", "(a_up) with a vocabulary and LDA of its own views",
                               a_descriptors, up_labels, own->held, options, is_object));
  }
  return l;
}

}  // namespace

HeldOutView render_held_out_view(sim::SimulatedRobot& alone, const std::string& name, int id, int v,
                                 int count) {
  assert(count > 0 && v >= 0 && v < count);
  const double yaw = 2 * std::numbers::pi * v / count;
  alone.place({{name, kHeldOutCentre, yaw}});
  HeldOutView view;
  view.image = alone.look().image;
  view.mask = alone.ground_truth_mask() == id;
  return view;
}

SelfSupervisionScore score_self_supervision(const Learning& learning,
                                            const GroundTruthAttendant& attendant,
                                            const std::vector<std::string>& objects,
                                            const topics::LdaModel& model,
                                            const features::Vocabulary& vocabulary,
                                            const SelfSupervisionOptions& options) {
  SelfSupervisionScore s;
  const int c_count = learning.classes;
  const auto& pushes = attendant.pushes();
  const auto& rounds = attendant.rounds();
  // The class of round r (SelfSupervisionOptions::rounds merges rounds; otherwise round r's).
  const auto class_of = [&learning](int r) {
    if (r < 0) return -1;
    if (learning.round_class.empty()) return r;
    const auto u = static_cast<std::size_t>(r);
    return u < learning.round_class.size() ? learning.round_class[u] : -1;
  };
  // Each class is named after the object the ground truth says it pushed most (learn pushes).
  s.class_object.assign(static_cast<std::size_t>(c_count), "");
  s.class_purity.assign(static_cast<std::size_t>(c_count), 0.0);
  int pure_views = 0;
  int all_views = 0;
  for (int c = 0; c < c_count; ++c) {
    s.class_object[static_cast<std::size_t>(c)] =
        pushed_most(pushes, [&class_of, c](int r) { return class_of(r) == c; });
    int pure = 0;
    int views = 0;
    for (const auto& p : pushes) {
      if (class_of(p.round) != c || p.phase != "learn") continue;
      views += p.views;
      if (!p.view_truth.empty() && p.view_truth == s.class_object[static_cast<std::size_t>(c)]) {
        pure += p.views;
      }
    }
    s.class_purity[static_cast<std::size_t>(c)] = fraction(pure, views);
    pure_views += pure;
    all_views += views;
  }
  s.purity = fraction(pure_views, all_views);
  for (std::size_t r = 0; r < rounds.size(); ++r) {
    s.round_object.push_back(
        pushed_most(pushes, [r](int round) { return round == static_cast<int>(r); }));
  }
  for (int c = 0; c < c_count; ++c) {
    // The class's first round (its own with one round an object).
    int first = -1;
    for (int r = 0; r < static_cast<int>(rounds.size()) && first < 0; ++r) {
      if (class_of(r) == c) first = r;
    }
    const bool seen = first >= 0;
    const auto f = static_cast<std::size_t>(std::max(first, 0));
    s.class_chosen.push_back(seen ? rounds[f].chosen : std::string());
    s.class_gap.push_back(seen ? rounds[f].least_gap : -1.0);
    s.class_blobs.push_back(seen ? rounds[f].blobs : std::vector<std::string>{});
  }
  // Each executed learn push as the ground truth saw it: "intended>moved+moved".
  s.class_learn_pushes.assign(static_cast<std::size_t>(c_count), {});
  s.class_learn_blobs.assign(static_cast<std::size_t>(c_count), {});
  for (const auto& p : pushes) {
    const int pc = class_of(p.round);
    if (p.phase != "learn" || !p.executed || pc < 0 || pc >= c_count) continue;
    std::string line = p.intended + ">";
    for (std::size_t i = 0; i < p.moved.size(); ++i) {
      if (i > 0) line += '+';
      line += p.moved[i];
    }
    s.class_learn_pushes[static_cast<std::size_t>(pc)].push_back(line);
    s.class_learn_blobs[static_cast<std::size_t>(pc)].push_back(p.blob_truth);
  }
  // Singulation, clearing pushes, intended-only, off the table.
  int singulated = 0;
  int executed = 0;
  int only = 0;
  int clear_pushes = 0;
  int cleared_objects = 0;
  for (int r = 0; r < static_cast<int>(rounds.size()); ++r) {
    if (rounds[static_cast<std::size_t>(r)].singulated) ++singulated;
    std::set<std::string> moved;
    for (const auto& p : pushes) {
      if (p.round != r || p.phase != "clear" || !p.executed) continue;
      ++clear_pushes;
      for (const auto& m : p.moved) {
        if (m != rounds[static_cast<std::size_t>(r)].chosen) moved.insert(m);
      }
    }
    cleared_objects += static_cast<int>(moved.size());
  }
  for (const auto& p : pushes) {
    if (!p.executed) continue;
    ++executed;
    if (p.only_intended) ++only;
    s.off_table += p.fell_off;
  }
  // Of the rounds run (C of them unless SelfSupervisionOptions::rounds allows more).
  s.singulation = fraction(singulated, std::max(c_count, static_cast<int>(rounds.size())));
  s.pushes_per_cleared =
      cleared_objects > 0 ? static_cast<double>(clear_pushes) / cleared_objects : 0.0;
  s.only_intended = fraction(only, executed);

  // Held-out views: each object alone at the table's centre, yaw stepped through 360 degrees.
  const sim::ObjectCatalogue catalogue = sim::ObjectCatalogue::load_default();
  const topics::MotModel& mot = learning.model;
  std::vector<std::string> columns;
  for (int m = 0; m < mot.num_classes(); ++m) {
    const int c = learning.model_class[static_cast<std::size_t>(m)];
    columns.push_back(core::cat({learning.class_names[static_cast<std::size_t>(c)], " (",
                                 s.class_object[static_cast<std::size_t>(c)], ")"}));
  }
  // Argmax theta: topics merged onto the learner's classes by its own training views.
  std::vector<int> train_labels(learning.views.labels.size(), -1);
  for (std::size_t i = 0; i < train_labels.size(); ++i) {
    for (int m = 0; m < mot.num_classes(); ++m) {
      if (learning.model_class[static_cast<std::size_t>(m)] == learning.views.labels[i]) {
        train_labels[i] = m;
      }
    }
  }
  std::optional<recognition::TopicMapping> mapping;
  if (mot.num_classes() > 0) {
    mapping = recognition::map_topics(learning.views.theta, train_labels, mot.num_classes());
  }
  // The training views' words (the pooled and colour classifiers) are one document a view.
  const auto check_view_words = [&learning] {
    if (static_cast<Eigen::Index>(learning.views.words.num_documents()) !=
        learning.views.theta.rows()) {
      throw Error(core::cat(
          {"selfsupervise scoring: ", std::to_string(learning.views.words.num_documents()),
           " view documents for ", std::to_string(learning.views.theta.rows()),
           " training views"}));
    }
  };
  // The pooled words classifier's multinomials from the training views' words (model classes).
  const bool want_words = options.pooled_score || options.mot_classifier == MotClassifier::kPooled;
  Eigen::MatrixXd log_phi;
  if (want_words && mot.num_classes() > 0) {
    check_view_words();
    log_phi = weighted_word_multinomials(learning.views.words, train_labels, mot.num_classes());
  }
  // With colour words: each class's colour multinomial from its views, every view weighing alike
  // (colour_multinomials); c is also scored by the colour words alone (classify_by_colour). Not
  // when the learning kept no view words (learn's scoring: it has its own colour figure,
  // LearnWordScore::colour); learn_by_pushing always keeps them.
  const bool colour_figure = options.colour_words && (learning.views.words.num_documents() > 0 ||
                                                      learning.views.theta.rows() == 0);
  const bool by_colour = colour_figure && mot.num_classes() > 0;
  if (options.mot_classifier == MotClassifier::kColour && !colour_figure) {
    throw Error(
        "selfsupervise scoring: mot_classifier colour needs colour words and the views' "
        "words");
  }
  const int colour_from = vocabulary.size();
  Eigen::MatrixXd log_colour;
  if (by_colour) {
    check_view_words();
    log_colour =
        colour_multinomials(learning.views.words, train_labels, mot.num_classes(), colour_from);
  }
  std::vector<topics::Corpus> held_words(objects.size(), topics::Corpus(model.num_words()));
  std::vector<int> truth_rows;
  std::vector<int> mot_pred;
  std::vector<int> argmax_pred;
  const bool ladder = options.oracle_ladder;
  std::vector<Eigen::MatrixXd> held(objects.size());
  // (a0): held-out-like renders (alone at the centre, yaws between the held-out ones) and the
  // same alone at random places and yaws of the scatter region; their labels.
  topics::Corpus a0_corpus(vocabulary.size());
  topics::Corpus a0_table_corpus(vocabulary.size());
  std::vector<std::string> a0_labels;
  std::vector<std::string> a0_table_labels;
  topics::Corpus alone_corpus(vocabulary.size());
  std::vector<std::string> alone_labels;
  std::optional<OwnDescriptors> own;
  if (ladder && options.own_model_rungs) {
    own.emplace();
    own->held.resize(objects.size());
  }
  std::optional<Probes> probes;
  if (ladder && options.ladder_probes) {
    probes.emplace(
        vocabulary.size(),
        std::initializer_list<std::pair<const char*, const char*>>{
            {"p_last", "probe: each push's last frame, the true mask (a_last where a render is)"},
            {"p_alone", "probe: the render of the same pose (a_alone where a frame is)"},
            {"p_last_d0", "probe: the frame, the true mask not grown"},
            {"p_last_rmask", "probe: the frame under the render's (unoccluded) mask"},
            {"p_noarm", "probe: the frame, the arm's pixels from the render"},
            {"p_noother", "probe: the frame, other objects' pixels from the render"},
            {"p_frame_obj", "probe: the render with the frame's object pixels, the frame's mask"},
            {"p_frame_obj_rmask", "probe: the same under the frame's and render's masks"},
            {"p_clean", "probe: the frame's features whose window reaches no arm or other object"},
            {"p_clean_arm", "probe: the frame's features whose window reaches no arm"},
            {"p_render_obj", "probe: the frame with the render's object pasted, render's mask"}});
  }
  for (std::size_t oi = 0; oi < objects.size(); ++oi) {
    ObjectScore os;
    os.name = objects[oi];
    for (const auto& p : pushes) {
      if (p.phase == "learn" && p.executed && p.intended == os.name) {
        ++os.learn_pushes;
        os.turn_deg += p.turn_deg;
        if (p.lying_before) ++os.learn_lying;
      }
      if (!p.executed) continue;
      const bool fell = std::find(p.tipped.begin(), p.tipped.end(), os.name) != p.tipped.end();
      if (p.intended == os.name) {
        ++os.pushes;
        if (fell) ++os.tipped;
      } else if (fell) {
        ++os.tipped_by_others;
      }
    }
    if (os.learn_pushes > 0) os.turn_deg /= os.learn_pushes;
    for (const auto& r : rounds) {
      if (r.chosen == os.name) ++os.chosen;
    }
    for (int c = 0; c < c_count; ++c) {
      if (s.class_object[static_cast<std::size_t>(c)] != os.name) continue;
      os.classes.push_back(c);
      os.views += learning.views_per_class[static_cast<std::size_t>(c)];
      os.purity = s.class_purity[static_cast<std::size_t>(c)];
    }
    std::vector<double> yaws;
    for (const auto& r : rounds) {
      if (r.chosen == os.name) yaws.insert(yaws.end(), r.yaws.begin(), r.yaws.end());
    }
    os.yaw_range_deg = yaw_coverage_deg(yaws);
    if (mot.num_classes() == 0 && !ladder) {
      s.objects.push_back(os);
      continue;
    }
    sim::TableOptions table;
    table.objects = {os.name};
    table.seed = options.seed;
    table.width = options.width;
    table.height = options.height;
    sim::SimulatedRobot alone(table, catalogue);
    const int id = alone.ground_truth().at(0).id;
    topics::Corpus corpus(
        features::document_vocabulary_size(vocabulary, options.document_colour()));
    for (int v = 0; v < options.held_out; ++v) {
      const HeldOutView view = render_held_out_view(alone, os.name, id, v, options.held_out);
      features::Features f =
          masked_features(view.image, view.mask, options.features, options.dilate);
      if (f.size() < options.min_features) continue;
      corpus.add_tokens(
          features::document_words(vocabulary, view.image, f, options.document_colour()));
      if (own) own->held[oi].push_back(std::move(f.descriptors));
    }
    if (ladder) {
      const sim::ObjectType* type = &catalogue.get(os.name);
      for (int v = 0; v < kLadderRenders; ++v) {
        const double yaw = 2 * std::numbers::pi * (v + 0.5) / kLadderRenders;
        for (int where = 0; where < 2; ++where) {
          sim::Placement place{os.name, kHeldOutCentre, yaw};
          if (where == 1) {
            const auto places = sim::scatter_placements(
                {type}, sim::ScatterRegion{},
                core::stream_seed(options.seed, kLadderStream, oi, static_cast<std::uint64_t>(v)));
            if (places.empty()) continue;
            place = places.front();
          }
          alone.place({place});
          const robot::Look look = alone.look();
          const cv::Mat mask = alone.ground_truth_mask() == id;
          cv::Mat desc = masked_descriptors(look.image, mask, options.features, options.dilate);
          if (desc.rows < options.min_features) continue;
          (where == 0 ? a0_corpus : a0_table_corpus)
              .add_tokens(features::bag_of_words(vocabulary, desc));
          (where == 0 ? a0_labels : a0_table_labels).push_back(os.name);
          if (own && where == 0) own->a0.push_back(std::move(desc));
        }
      }
      // (a_alone): the object alone where and as each of its pushes left it (the pose of the
      // push's last view): a_last without the arm, the other objects and the push's motion.
      const std::vector<ViewTruth>& views = attendant.views();
      for (std::size_t vi = 0; vi < views.size(); ++vi) {
        const ViewTruth& v = views[vi];
        const bool last = vi + 1 == views.size() || views[vi + 1].episode != v.episode;
        if (!last || !v.posed || v.intended != os.name) continue;
        alone.place({{os.name, v.position, v.yaw}});
        const robot::Look look = alone.look();
        const cv::Mat mask = alone.ground_truth_mask() == id;
        const auto doc =
            masked_document(look.image, mask, vocabulary, options.features, options.dilate);
        if (static_cast<int>(doc.size()) < options.min_features) continue;
        alone_corpus.add_tokens(doc);
        alone_labels.push_back(os.name);
      }
      // The probes: each push's last frame against the render of the same pose.
      if (probes) {
        std::optional<episode::Episode> pe;
        for (std::size_t vi = 0; vi < views.size(); ++vi) {
          const ViewTruth& v = views[vi];
          const bool last = vi + 1 == views.size() || views[vi + 1].episode != v.episode;
          if (!last || !v.posed || v.intended != os.name || v.episode.empty() || v.frame < 0) {
            continue;
          }
          if (!pe || pe->dir() != v.episode) pe.emplace(episode::read_episode(v.episode));
          if (!pe->info().has_masks) continue;
          const int fid = object_id(*pe, v.intended);
          if (fid < 0) continue;
          alone.place({{os.name, v.position, v.yaw}});
          const robot::Look look = alone.look();
          const cv::Mat frame = pe->frame(v.frame);
          const cv::Mat fids = pe->mask(v.frame);
          if (frame.size() != look.image.size() || frame.type() != look.image.type()) continue;
          // The render's ids carry the frame's id for the object (one object, one id).
          probes->stat(os.name, "toppled", v.upright ? 0 : 1);
          probe_push_view(*probes, os.name, fid, frame, fids, look.image,
                          alone.ground_truth_mask() == id, vocabulary, options);
        }
      }
    }
    held_words[oi] = corpus;
    os.held_out = static_cast<int>(corpus.num_documents());
    if (os.held_out > 0) {
      // A model made with weighted colour words weighs them itself (LdaModel::word_weights).
      held[oi] = recognition::document_theta(model, corpus).theta;
    }
    if (os.held_out > 0 && mot.num_classes() > 0) {
      const Eigen::MatrixXd& theta = held[oi];
      std::optional<topics::MotClassification> colour_cls;
      if (by_colour) colour_cls = classify_by_colour(mot, log_colour, corpus, colour_from);
      topics::MotClassification cls;
      switch (options.mot_classifier) {
        case MotClassifier::kPooled:
          cls = topics::pool_word_multinomials(mot, topics::classify_mot_words(mot, model, corpus),
                                               log_phi, corpus, options.mot_word_weight);
          break;
        case MotClassifier::kColour:
          assert(colour_cls);  // checked above
          cls = *colour_cls;
          break;
        case MotClassifier::kTheta:
          cls = topics::classify_mot(mot, theta);
          break;
      }
      std::vector<int> topic(static_cast<std::size_t>(theta.rows()));
      for (Eigen::Index d = 0; d < theta.rows(); ++d) {
        Eigen::Index k = 0;
        theta.row(d).maxCoeff(&k);
        topic[static_cast<std::size_t>(d)] = static_cast<int>(k);
      }
      const std::vector<int> mapped = recognition::mapped_classes(topic, *mapping);
      int right_mot = 0;
      int right_argmax = 0;
      int right_colour = 0;
      for (std::size_t d = 0; d < cls.predicted.size(); ++d) {
        const auto name_of = [&](int m) {
          return m < 0 ? std::string()
                       : s.class_object[static_cast<std::size_t>(
                             learning.model_class[static_cast<std::size_t>(m)])];
        };
        if (name_of(cls.predicted[d]) == os.name) ++right_mot;
        if (name_of(mapped[d]) == os.name) ++right_argmax;
        if (colour_cls && name_of(colour_cls->predicted[d]) == os.name) ++right_colour;
        truth_rows.push_back(static_cast<int>(oi));
        mot_pred.push_back(cls.predicted[d]);
        argmax_pred.push_back(mapped[d]);
      }
      os.mot_accuracy = fraction(right_mot, os.held_out);
      os.argmax_accuracy = fraction(right_argmax, os.held_out);
      if (colour_cls) os.colour_accuracy = fraction(right_colour, os.held_out);
    }
    s.objects.push_back(os);
  }
  s.mot = recognition::confusion_matrix(truth_rows, mot_pred, objects, columns);
  s.argmax = recognition::confusion_matrix(truth_rows, argmax_pred, objects, columns);
  int right_mot = 0;
  int right_argmax = 0;
  int n = 0;
  for (const auto& o : s.objects) {
    right_mot += static_cast<int>(std::lround(o.mot_accuracy * o.held_out));
    right_argmax += static_cast<int>(std::lround(o.argmax_accuracy * o.held_out));
    n += o.held_out;
  }
  s.mot_accuracy = fraction(right_mot, n);
  s.argmax_accuracy = fraction(right_argmax, n);
  if (colour_figure) {
    // Every object and c get a colour figure (0 without views or classes, as the MoT's).
    int right_colour = 0;
    for (auto& o : s.objects) {
      if (!o.colour_accuracy) o.colour_accuracy = 0.0;
      right_colour += static_cast<int>(std::lround(*o.colour_accuracy * o.held_out));
    }
    s.colour_accuracy = fraction(right_colour, n);
  }
  if (options.pooled_score && mot.num_classes() > 0) {
    // c by the pooled words classifier at each weight, and with each push's views counted once.
    const auto by_words = by_words_of(mot, model, held_words);
    const auto is_right = [&](int m, std::size_t oi) {
      return s.class_object[static_cast<std::size_t>(
                 learning.model_class[static_cast<std::size_t>(m)])] == objects[oi];
    };
    s.pooled.emplace();
    for (const double w : kPooledWeights) {
      s.pooled->push_back(pooled_figure(mot, log_phi, held_words, by_words, w, false, is_right));
    }
    const Eigen::MatrixXd once =
        weighted_word_multinomials(learning.views.words, train_labels, mot.num_classes(),
                                   counts_once(learning.views.labels, learning.views.push));
    s.pooled->push_back(
        pooled_figure(mot, once, held_words, by_words, options.mot_word_weight, true, is_right));
  }
  if (ladder) {
    s.ladder =
        oracle_ladder(learning, attendant, s, objects, held, a0_corpus, a0_labels, a0_table_corpus,
                      a0_table_labels, alone_corpus, alone_labels, model, vocabulary, options,
                      held_words, probes ? &*probes : nullptr, own ? &*own : nullptr);
  }
  return s;
}

}  // namespace proprio::loop

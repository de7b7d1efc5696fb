// The self-supervision loop (thesis 7.2 a-d): the learner's side, on robot::Robot only.
#include "proprio/loop/self_supervision.hpp"

#include <spdlog/spdlog.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <numbers>
#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "arm_image.hpp"
#include "blob_tracking.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/progress.hpp"
#include "proprio/core/random.hpp"
#include "proprio/core/text.hpp"
#include "proprio/episode/episode.hpp"
#include "proprio/features/colour_words.hpp"
#include "proprio/features/features.hpp"
#include "proprio/features/mask_morphology.hpp"
#include "proprio/loop/depth_alone.hpp"
#include "proprio/recognition/mot.hpp"
#include "proprio/topics/corpus.hpp"

namespace proprio::loop {

namespace fs = std::filesystem;

namespace {

constexpr std::uint64_t kChoiceStream = 0x63686f696365ULL;  // core::stream_seed key: choices
constexpr std::uint64_t kPlanStream = 0x706c616eULL;        // core::stream_seed key: push plans

constexpr double kTrackRadius =
    0.08;                        // a blob is the chosen object when its centre is this near, m
constexpr double kStill = 0.01;  // a blob that moved less than this did not move, m
constexpr double kApproachStep = 0.03;      // approach added after a refusal, m
constexpr double kMaxExtraApproach = 0.12;  // at most, m
constexpr int kSides = 8;                   // (c): sides tried when a push is out of reach
constexpr double kSidePush = 0.08;          // (c): how far those pushes go, m
constexpr double kClearMargin = 0.04;       // (b): pushed this much beyond the clearance, m
constexpr int kRechoices = 2;         // (b): choices again in a round after the chosen one was lost
constexpr double kFindRadius = 0.12;  // a pushed object is looked for this near its target, m
constexpr double kMaxLearnPush = 0.12;  // (c): the object is moved at most this far a push, m
constexpr double kFreeStep = 0.02;      // (b) free_space: the grid of free spots, m
constexpr double kFreeGain = 0.02;      // (b) free_space: a spot must give this much more room, m
constexpr int kFreeTries = 4;           // (b) free_space: spots planned at most per look
constexpr double kFreeCorridor = 0.02;  // (b) free_space: its corridor keeps this from others, m
constexpr double kGoldenAngle = 2.399963229728653;  // rad

// The blob of `view` nearest `centre` within kTrackRadius; -1 none.
int track(const planning::PlanningView& view, const Eigen::Vector2d& centre,
          double radius = kTrackRadius) {
  return detail::nearest_blob(view, centre, radius);
}

using detail::blob_mask;

double point_segment(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double l2 = ab.squaredNorm();
  const double t = l2 > 0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

bool inside(const std::vector<Eigen::Vector2d>& poly, const Eigen::Vector2d& p) {
  bool in = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Eigen::Vector2d& a = poly[i];
    const Eigen::Vector2d& b = poly[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) &&
        p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x()) {
      in = !in;
    }
  }
  return in;
}

// The learner's state of one run.
class Learner {
 public:
  Learner(robot::Robot& robot, TableAttendant& attendant, int classes,
          const topics::LdaModel& model, const features::Vocabulary& vocabulary,
          const SelfSupervisionOptions& options, fs::path episodes, const fs::path& log_path)
      : robot_(robot),
        attendant_(attendant),
        model_(model),
        vocabulary_(vocabulary),
        o_(options),
        episodes_(std::move(episodes)),
        rng_(core::Rng::stream(options.seed, kChoiceStream)),
        colour_(options.document_colour()),
        words_(features::document_vocabulary_size(vocabulary, colour_)) {
    objects_ = classes;
    // rounds: up to that many rounds, each its own class until merge_into_classes().
    const int rounds = options.rounds > 0 ? std::max(classes, options.rounds) : classes;
    out_.classes = rounds;
    for (int c = 0; c < rounds; ++c) {
      out_.class_names.push_back(
          core::cat({rounds > classes ? "round_" : "object_", std::to_string(c + 1)}));
    }
    out_.views_per_class.assign(static_cast<std::size_t>(rounds), 0);
    out_.stop_reasons.assign(static_cast<std::size_t>(rounds), "");
    out_.views.theta.resize(0, model.num_topics());
    out_.views.words = topics::Corpus(model.num_words());
    class_looks_.resize(static_cast<std::size_t>(rounds));
    class_look_words_.assign(static_cast<std::size_t>(rounds), Eigen::VectorXd::Zero(words_));
    class_look_colours_.assign(static_cast<std::size_t>(rounds),
                               Eigen::VectorXd::Zero(options.colour.count()));
    class_look_colour_list_.assign(static_cast<std::size_t>(rounds), {});
    class_descriptors_.resize(static_cast<std::size_t>(rounds));
    if (!log_path.empty()) log_file_.open(log_path);
  }

  Learning run(bool progress) {
    const auto t0 = std::chrono::steady_clock::now();
    const auto c = static_cast<std::size_t>(out_.classes);
    core::ProgressBar bar(c * static_cast<std::size_t>(o_.pushes), "self-supervision", progress);
    const robot::Look first = robot_.look();
    // The planner's blob scales are for 640 x 480 images: scale them with the image, so that
    // neighbouring objects do not merge into one blob in a smaller image.
    const double scale = first.image.cols / 640.0;
    plan_options_ = o_.plan;
    if (o_.topple_ratio > 0) plan_options_.topple_ratio = o_.topple_ratio;
    if (o_.topple_offset > 0) plan_options_.topple_offset = o_.topple_offset;
    plan_options_.grid_step = std::max(2, static_cast<int>(std::lround(o_.plan.grid_step * scale)));
    plan_options_.patch = std::max(4, static_cast<int>(std::lround(o_.plan.patch * scale)));
    plan_options_.blobs.sigma = o_.plan.blobs.sigma * scale;
    centre_ = robot::pixel_to_table(
        first.camera, Eigen::Vector2d(first.image.cols / 2.0, first.image.rows / 2.0));
    log({.event = "start",
         .classes = out_.classes,
         .topics = model_.num_topics(),
         .words = words_,
         .work_centre = xy(centre_)});
    for (int r = 0; r < out_.classes; ++r) {
      if (r > 0) {
        try {
          log({.event = "rescatter", .round = r, .what = attendant_.rescatter(r)});
        } catch (const Error& e) {
          // The world could not put the objects down again: stop with the reason.
          fault(r, "rescatter-failed", e.what());
          for (int q = r; q < out_.classes; ++q) {
            out_.stop_reasons[static_cast<std::size_t>(q)] = "the re-scatter failed";
          }
          bar.tick(static_cast<std::size_t>(out_.classes - r) *
                   static_cast<std::size_t>(o_.pushes));
          break;
        }
      }
      round(r, bar);
      rounds_run_ = r + 1;
      if (merging() && rounds_run_ >= objects_ && rounds_run_ < out_.classes && judged_done()) {
        bar.tick(static_cast<std::size_t>(out_.classes - rounds_run_) *
                 static_cast<std::size_t>(o_.pushes));
        break;
      }
    }
    bar.finish();
    if (keeps_colours()) {
      out_.round_colours.assign(class_look_colours_.begin(),
                                class_look_colours_.begin() + rounds_run_);
    }
    if (merging()) {
      merge_into_classes();
    } else {
      for (int r = 0; r < rounds_run_; ++r) out_.round_class.push_back(r);
    }
    fit();
    out_.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    log({.event = "end",
         .views = static_cast<int>(out_.views.labels.size()),
         .pushes_clear = out_.pushes_clear,
         .pushes_learn = out_.pushes_learn,
         .faults = out_.faults,
         .seconds = out_.seconds});
    return std::move(out_);
  }

 private:
  void log(SelfSupervisionDecision d) {
    if (log_file_.is_open()) {
      log_file_ << core::fields_to_json(d).dump() << '\n';
      log_file_.flush();
    }
    out_.log.push_back(std::move(d));
  }

  void fault(int r, const std::string& what, const std::string& message) {
    ++out_.faults;
    spdlog::warn("self-supervision, round {}: {}: {}", r, what, message);
    log({.event = "fault", .round = r, .message = message, .fault = what});
  }

  planning::PlanningView look() {
    const robot::Look l = robot_.look();
    size_ = l.image.size();
    image_ = l.image;
    planning::PlanningView view = planning::look_for_objects(l, region_, plan_options_);
    if (o_.split_merged && splitting_ && static_cast<int>(view.objects.size()) < objects_) {
      const std::size_t seen = view.objects.size();
      const std::vector<int> split = split_merged_blobs(view, l.image, objects_, o_.min_features,
                                                        o_.split_colour, region_, plan_options_);
      if (!split.empty()) {
        std::string which;
        for (const int b : split)
          which += core::cat({which.empty() ? "" : ", ", std::to_string(b)});
        log({.event = "split",
             .round = round_,
             .why = core::cat({std::to_string(seen), " blobs for ", std::to_string(objects_),
                               " objects: blob(s) ", which,
                               " split in two by k-means on positions and colours; ",
                               std::to_string(view.objects.size()), " blobs now"}),
             .blobs = putative_object_records(view, false)});
      }
    }
    // table_colours_out: once a look; every blob_colours call reads the last look's blobs.
    if (o_.table_colours_out) table_words_ = table_colour_words(image_, view, o_.colour);
    return view;
  }

  // The documents' theta under the model (a model made with weighted colour words weighs them
  // alike itself: LdaModel::word_weights).
  Eigen::MatrixXd theta_of(const std::vector<std::vector<std::int32_t>>& docs) {
    topics::Corpus corpus(words_);
    for (const auto& d : docs) corpus.add_tokens(d);
    return recognition::document_theta(model_, corpus).theta;
  }

  // The document of blob `k` of `view` in the last look's image (empty: too few features);
  // with `desc`, its descriptors too (empty with the document).
  std::vector<std::int32_t> blob_document(const planning::PlanningView& view, int k,
                                          cv::Mat* desc = nullptr) {
    features::Features f =
        masked_features(image_, blob_mask(view.objects[static_cast<std::size_t>(k)], size_),
                        o_.features, o_.dilate);
    // min_features counts features: with colour words a document has two words a feature.
    std::vector<std::int32_t> d;
    if (f.size() >= o_.min_features) d = features::document_words(vocabulary_, image_, f, colour_);
    if (desc) *desc = d.empty() ? cv::Mat() : f.descriptors;
    return d;
  }

  // claims_by kColour: how many pixels of blob `k` of `view` (its own mask, not dilated) have
  // each colour word, in the last look's image.
  Eigen::VectorXd blob_colours(const planning::PlanningView& view, int k) const {
    const std::vector<double> counts = features::colour_word_counts(
        image_, blob_mask(view.objects[static_cast<std::size_t>(k)], size_), o_.colour);
    const Eigen::Map<const Eigen::VectorXd> v(counts.data(),
                                              static_cast<Eigen::Index>(counts.size()));
    if (!o_.table_colours_out) return v;
    // table_colours_out: the table's words of this look (image_ and view are the same look).
    return without_table_colours(v, table_words_);
  }

  // moved_colours: round r's colours gain what a learn push moved: the pixels of blob c of `view`
  // (the look before, `before`) and of blob `now` of `after` (the look after, image_) that
  // changed (moved_pixels), each image's colours in its own blob. Returns the pixels added.
  double add_moved_colours(int r, const cv::Mat& before, const planning::PlanningView& view, int c,
                           const planning::PlanningView& after, int now) {
    auto& colours = class_look_colours_[static_cast<std::size_t>(r)];
    // What changed anywhere, once; each blob keeps its own part of it.
    const cv::Mat changed =
        moved_pixels(before, image_, cv::Mat(size_, CV_8UC1, cv::Scalar(255)), kMovedLevels);
    const auto add = [&](const cv::Mat& image, const planning::PutativeObject& o) {
      const cv::Mat moved = changed & blob_mask(o, size_);
      const std::vector<double> counts = features::colour_word_counts(image, moved, o_.colour);
      const Eigen::Map<const Eigen::VectorXd> v(counts.data(),
                                                static_cast<Eigen::Index>(counts.size()));
      colours += v;
      return v.sum();
    };
    double n = add(before, view.objects[static_cast<std::size_t>(c)]);
    if (now >= 0) n += add(image_, after.objects[static_cast<std::size_t>(now)]);
    return n;
  }

  // Whether a claim signal in use (claims_by or other_claims_by) is `s`.
  [[nodiscard]] bool uses(ClaimSignal s) const {
    return o_.claims_by == s || o_.other_claims_by == s;
  }
  // Whether the rounds' looks keep their pixel colours: for the claims by colour, refind_colour,
  // or the rounds judged the same object by colour.
  [[nodiscard]] bool keeps_colours() const {
    return uses(ClaimSignal::kColour) || o_.refind_colour > 0 || by_colour();
  }
  [[nodiscard]] bool by_colour() const {
    return merging() && o_.same_object_by == RoundSimilarity::kColour;
  }
  // Whether the classes' descriptors come from `from` (and a signal uses them).
  [[nodiscard]] bool descriptors_from(DescriptorSource from) const {
    return uses(ClaimSignal::kDescriptors) && o_.descriptor_source == from;
  }
  // Whether the classes' descriptors come from looks (all of them or the first only).
  [[nodiscard]] bool descriptors_from_looks() const {
    return descriptors_from(DescriptorSource::kLooks) ||
           descriptors_from(DescriptorSource::kFirstLook);
  }

  // The documents of the blobs of `view` that have enough features, and those blobs' indices.
  // With `descriptors`, the blobs' descriptors too.
  struct BlobDocuments {
    std::vector<std::vector<std::int32_t>> docs;
    std::vector<int> rows;
    std::vector<cv::Mat> descriptors;
  };
  BlobDocuments blob_documents(const planning::PlanningView& view, bool descriptors = false) {
    BlobDocuments b;
    for (int k = 0; k < static_cast<int>(view.objects.size()); ++k) {
      cv::Mat m;
      auto d = blob_document(view, k, descriptors ? &m : nullptr);
      if (!d.empty()) {
        b.docs.push_back(std::move(d));
        b.rows.push_back(k);
        if (descriptors) b.descriptors.push_back(m);
      }
    }
    return b;
  }

  // The blobs of `view` with enough features: their documents, indices and thetas (rows), and
  // per blob of the view its theta (empty: too few features), its words (empty: the same) and,
  // when a claim signal uses them (claims_by or other_claims_by descriptors), its descriptors,
  // and (a signal colour) its pixels' colour-word counts (empty: too few features, as theta).
  struct BlobThetas {
    std::vector<std::vector<std::int32_t>> docs;
    std::vector<int> rows;
    Eigen::MatrixXd theta;
    std::vector<Eigen::VectorXd> per_blob;
    std::vector<std::vector<std::int32_t>> words;
    std::vector<cv::Mat> descriptors;
    std::vector<Eigen::VectorXd> colours;
  };
  BlobThetas blob_thetas(const planning::PlanningView& view) {
    BlobThetas t;
    auto [docs, rows, desc] = blob_documents(view, uses(ClaimSignal::kDescriptors));
    t.per_blob.resize(view.objects.size());
    t.words.resize(view.objects.size());
    t.descriptors.resize(view.objects.size());
    t.colours.resize(view.objects.size());
    if (!docs.empty()) {
      t.theta = theta_of(docs);
      for (std::size_t i = 0; i < rows.size(); ++i) {
        const auto b = static_cast<std::size_t>(rows[i]);
        t.per_blob[b] = t.theta.row(static_cast<Eigen::Index>(i)).transpose();
        t.words[b] = docs[i];
        if (i < desc.size()) t.descriptors[b] = desc[i];
        if (uses(ClaimSignal::kColour)) t.colours[b] = blob_colours(view, rows[i]);
      }
    }
    t.docs = std::move(docs);
    t.rows = std::move(rows);
    return t;
  }

  // claims_by kViewWords: per class (per group of rounds when merging) its views' word counts.
  // claims_by kLookWords (`looks`): per class its looks' word counts instead.
  std::vector<Eigen::VectorXd> class_word_counts(bool looks = false) const {
    return per_class(looks ? class_look_words_ : round_counts(), words_);
  }

  // Per-round values as per class: one a round class (C of them), or combined by `add` over
  // each group of rounds the robot judges one object when merging (merge_rounds; judge()).
  template <typename T, typename Add>
  std::vector<T> grouped(const std::vector<T>& per_round, const T& empty, Add add) const {
    if (!merging()) {
      std::vector<T> out(class_looks_.size(), empty);
      for (std::size_t r = 0; r < per_round.size() && r < out.size(); ++r) out[r] = per_round[r];
      return out;
    }
    const RoundMerge m = judge();
    std::vector<T> out(static_cast<std::size_t>(m.distinct), empty);
    for (std::size_t r = 0; r < m.judged.size() && r < per_round.size(); ++r) {
      if (m.judged[r] >= 0) add(out[static_cast<std::size_t>(m.judged[r])], per_round[r]);
    }
    return out;
  }

  // Counts of length `length` per round, as per class, summed over a group's rounds.
  std::vector<Eigen::VectorXd> per_class(const std::vector<Eigen::VectorXd>& counts,
                                         Eigen::Index length) const {
    return grouped(counts, Eigen::VectorXd::Zero(length).eval(),
                   [](Eigen::VectorXd& to, const Eigen::VectorXd& from) { to += from; });
  }

  // Lists per round, as per class, a group's rounds' lists one after another.
  template <typename T>
  std::vector<std::vector<T>> per_class_lists(const std::vector<std::vector<T>>& lists) const {
    return grouped(lists, std::vector<T>{}, [](std::vector<T>& to, const std::vector<T>& from) {
      to.insert(to.end(), from.begin(), from.end());
    });
  }

  // claims_by kColour: per class (per group of rounds when merging) its looks' colour
  // distribution (the pooled counts normalised; empty: no looks yet, so no part in the claims).
  // colour_by_look: each look's distribution instead (choose_unlearned takes the least distance
  // to any of a class's looks).
  std::vector<std::vector<Eigen::VectorXd>> class_colours() const {
    if (o_.colour_by_look) return per_class_lists(class_look_colour_list_);
    const std::vector<Eigen::VectorXd> counts = per_class(class_look_colours_, o_.colour.count());
    std::vector<std::vector<Eigen::VectorXd>> out(counts.size());
    for (std::size_t c = 0; c < counts.size(); ++c) {
      if (counts[c].sum() > 0) out[c].push_back(counts[c] / counts[c].sum());
    }
    return out;
  }

  // (d)'s claims on the blobs of `view` by claims_by (choose_unlearned, by_words or
  // by_descriptors) and, a diagnostic only when asked (other_claims_by), another signal's claims
  // on the same blobs (empty: none asked, or it has no class yet).
  struct Claims {
    BlobThetas blobs;
    NextChoice next;
    std::vector<int> other;
    bool any = false;  // some class takes part in the claims in use
  };
  // Whether some learned class has looks (any_looks) or views (any_views).
  [[nodiscard]] bool any_looks() const {
    return std::any_of(class_looks_.begin(), class_looks_.end(),
                       [](const auto& l) { return !l.empty(); });
  }
  [[nodiscard]] bool any_views() const {
    return std::any_of(out_.views.labels.begin(), out_.views.labels.end(),
                       [&](int r) { return r >= 0 && r < rounds_run_; });
  }
  [[nodiscard]] bool any_descriptors() const {
    return std::any_of(class_descriptors_.begin(), class_descriptors_.end(),
                       [](const cv::Mat& m) { return !m.empty(); });
  }
  [[nodiscard]] bool any_claims() const {
    return o_.claims_by == ClaimSignal::kViewWords     ? any_views()
           : o_.claims_by == ClaimSignal::kDescriptors ? any_descriptors()
                                                       : any_looks();
  }

  // claims_by kDescriptors: per class (per group of rounds when merging) its looks' descriptors.
  [[nodiscard]] std::vector<cv::Mat> class_descriptors() const {
    if (!merging()) return class_descriptors_;
    const RoundMerge m = judge();
    std::vector<cv::Mat> out(static_cast<std::size_t>(m.distinct));
    for (std::size_t r = 0; r < m.judged.size() && r < class_descriptors_.size(); ++r) {
      const int g = m.judged[r];
      if (g < 0 || class_descriptors_[r].empty()) continue;
      auto& to = out[static_cast<std::size_t>(g)];
      if (to.empty()) {
        to = class_descriptors_[r].clone();
      } else {
        cv::vconcat(to, class_descriptors_[r], to);
      }
    }
    return out;
  }

  // The claims of signal `s` on `blobs`; `any`: whether some class takes part in them.
  NextChoice claims_of(ClaimSignal s, const BlobThetas& blobs, bool& any) {
    const int words = words_;
    switch (s) {
      case ClaimSignal::kViewWords: {
        const auto counts = class_word_counts();
        any = std::any_of(counts.begin(), counts.end(), [](const auto& n) { return n.sum() > 0; });
        return choose_unlearned_by_words(blobs.words, counts, words);
      }
      case ClaimSignal::kLookWords:
      case ClaimSignal::kFirstLookWords:
        any = any_looks();
        return choose_unlearned_by_words(blobs.words, class_word_counts(true), words);
      case ClaimSignal::kDescriptors:
        any = any_descriptors();
        return choose_unlearned_by_descriptors(blobs.descriptors, class_descriptors(),
                                               o_.descriptor_ratio, o_.descriptor_min_share);
      case ClaimSignal::kColour: {
        // The blobs' distributions (a blob of no pixels, unscored, stays empty).
        std::vector<Eigen::VectorXd> p(blobs.colours.size());
        for (std::size_t b = 0; b < p.size(); ++b) {
          const Eigen::VectorXd& n = blobs.colours[b];
          if (n.size() > 0 && n.sum() > 0) p[b] = n / n.sum();
        }
        const auto classes = class_colours();
        any = std::any_of(classes.begin(), classes.end(), [](const auto& l) { return !l.empty(); });
        return choose_unlearned(p, classes);
      }
      case ClaimSignal::kLooks:
      case ClaimSignal::kNone:
        break;
    }
    any = any_looks();
    // With rounds, each group of rounds the robot judges one object claims one blob by the looks
    // of all its rounds (rounds without views take no part: their object is not learned).
    return choose_unlearned(blobs.per_blob, per_class_lists(class_looks_));
  }

  Claims claims(const planning::PlanningView& view) {
    Claims c;
    c.blobs = blob_thetas(view);
    c.next = claims_of(o_.claims_by, c.blobs, c.any);
    if (o_.other_claims_by != ClaimSignal::kNone) {
      bool any_other = false;
      NextChoice other = claims_of(o_.other_claims_by, c.blobs, any_other);
      if (any_other) c.other = std::move(other.claimed_by);
    }
    return c;
  }

  // (a) / (d): the blob to learn. Round 0: at random; later (o_.choice): kLooks, the unclaimed
  // blob farthest from every class (choose_unlearned on the classes' looks, or by their views'
  // words: claims_by); kDirichlet, the blob whose best log Dir(theta | omega_c) + log p(c) over
  // the classes so far is least. `known`: the claims on `view` already made (recheck).
  int choose(int r, const planning::PlanningView& view, const Claims* known = nullptr) {
    const int n = static_cast<int>(view.objects.size());
    std::optional<Claims> made;
    if (!known && r > 0 && o_.choice == NextObjectRule::kLooks) made = claims(view);
    const Claims* cl = known ? known : made ? &*made : nullptr;
    const bool looks = cl && cl->any;
    if (r == 0 || (!looks && model_so_far_.objects.empty())) {
      const int k = static_cast<int>(rng_.index(static_cast<std::uint64_t>(n)));
      log({.event = "choose", .round = r, .blob = k, .why = "at random (7.2 a)"});
      return k;
    }
    std::optional<BlobThetas> own;
    if (!cl) own = blob_thetas(view);
    const BlobThetas& bt = cl ? cl->blobs : *own;
    const auto& rows = bt.rows;
    if (rows.empty()) {
      const int k = static_cast<int>(rng_.index(static_cast<std::uint64_t>(n)));
      log({.event = "choose",
           .round = r,
           .blob = k,
           .why = "at random: no blob has enough features to be scored"});
      return k;
    }
    std::vector<BlobScore> scores;
    scores.reserve(rows.size());
    for (const int k : rows) scores.push_back({k, 0.0});
    int best = rows[0];
    if (!model_so_far_.objects.empty()) {
      const topics::MotClassification cls = topics::classify_mot(model_so_far_, bt.theta);
      double best_score = std::numeric_limits<double>::infinity();
      for (std::size_t i = 0; i < rows.size(); ++i) {
        const double s = cls.log_score.row(static_cast<Eigen::Index>(i)).maxCoeff();
        scores[i].best_log_score = s;
        if (s < best_score) {
          best_score = s;
          best = rows[i];
        }
      }
    }
    if (!looks) {
      log({.event = "choose",
           .round = r,
           .blob = best,
           .why = "least likely under the classes learned so far (7.2 d)",
           .scores = std::move(scores)});
      return best;
    }
    const NextChoice& next = cl->next;
    for (BlobScore& bs : scores) {
      const auto b = static_cast<std::size_t>(bs.blob);
      bs.nearest = next.nearest[b];
      bs.nearest_class = next.nearest_class[b];
      bs.claimed_by = next.claimed_by[b];
      if (!cl->other.empty()) bs.other_claimed_by = cl->other[b];
    }
    const bool all_claimed =
        next.blob >= 0 && next.claimed_by[static_cast<std::size_t>(next.blob)] >= 0;
    const char* by = o_.claims_by == ClaimSignal::kViewWords        ? "views' words"
                     : o_.claims_by == ClaimSignal::kLookWords      ? "looks' words"
                     : o_.claims_by == ClaimSignal::kFirstLookWords ? "first looks' words"
                     : o_.claims_by == ClaimSignal::kDescriptors    ? "descriptors"
                     : o_.claims_by == ClaimSignal::kColour         ? "pixel colours"
                                                                    : "looks";
    log({.event = "choose",
         .round = r,
         .blob = next.blob,
         .why = all_claimed ? core::cat({"every blob is claimed by a learned class (by its ", by,
                                         "): the farthest (7.2 d)"})
                            : core::cat({"unclaimed by the learned classes' ", by,
                                         ", the farthest from them (7.2 d)"}),
         .scores = std::move(scores)});
    return next.blob;
  }

  // recheck_tries: after (b), the chosen object (at `chosen`) checked again against the learned
  // classes; while a class claims its blob and another blob is unclaimed, the round chooses
  // again and clears the new choice. Returns the object to learn (nullopt: lost while clearing).
  std::optional<Eigen::Vector2d> recheck(int r, Eigen::Vector2d chosen, int& index) {
    if (!any_claims()) return chosen;
    for (int t = 0; t < o_.recheck_tries; ++t) {
      const planning::PlanningView now = look();
      const int c = track(now, chosen);
      if (c < 0) return chosen;  // not found again here: (c) looks and tracks it as without
      const Claims made = claims(now);
      if (!made.any) return chosen;
      const NextChoice& cl = made.next;
      std::vector<BlobScore> scores;
      for (int k = 0; k < static_cast<int>(now.objects.size()); ++k) {
        const auto b = static_cast<std::size_t>(k);
        scores.push_back({.blob = k,
                          .best_log_score = 0.0,
                          .nearest = cl.nearest[b],
                          .nearest_class = cl.nearest_class[b],
                          .claimed_by = cl.claimed_by[b]});
      }
      const int by = cl.claimed_by[static_cast<std::size_t>(c)];
      const bool again = recheck_claimed(cl, c);
      log({.event = "recheck",
           .round = r,
           .blob = c,
           .why = by < 0 ? "after (b): no learned class claims the chosen blob: (c) starts"
                  : again
                      ? core::cat({"after (b): class ", std::to_string(by),
                                   " claims the chosen blob: choosing again, try ",
                                   std::to_string(t + 1), " of ", std::to_string(o_.recheck_tries)})
                      : core::cat({"after (b): class ", std::to_string(by),
                                   " claims the chosen blob, but every blob is claimed: (c) "
                                   "starts on it"}),
           .scores = std::move(scores),
           .blobs = putative_object_records(now, false)});
      if (!again) return chosen;
      const int k2 = choose(r, now, &made);
      attendant_.chose(r, now, k2);
      const std::optional<Eigen::Vector2d> next =
          clear(r, now.objects[static_cast<std::size_t>(k2)].centre, index);
      if (!next) return std::nullopt;
      chosen = *next;
    }
    return chosen;
  }

  // (c): the chosen object's look (blob `c` of the last look) kept for (d)'s kLooks choice.
  void keep_look(int r, const planning::PlanningView& view, int c) {
    cv::Mat desc;
    const auto d = blob_document(view, c, descriptors_from_looks() ? &desc : nullptr);
    if (d.empty()) return;
    // descriptor_source first-look: only the round's first look (the object after (b)).
    if (!descriptors_from(DescriptorSource::kFirstLook) ||
        class_descriptors_[static_cast<std::size_t>(r)].empty()) {
      add_descriptors(r, desc);
    }
    class_looks_[static_cast<std::size_t>(r)].push_back(theta_of({d}).row(0).transpose());
    if (keeps_colours()) {
      auto& colours = class_look_colours_[static_cast<std::size_t>(r)];
      // colour_first_look: the round's first look only (the object after (b)).
      // moved_colours: added after each push instead (add_moved_colours).
      if (!o_.moved_colours && (!o_.colour_first_look || colours.sum() <= 0)) {
        const Eigen::VectorXd look = blob_colours(view, c);
        colours += look;
        if (o_.colour_by_look && look.sum() > 0) {
          class_look_colour_list_[static_cast<std::size_t>(r)].push_back(look / look.sum());
        }
      }
    }
    auto& words = class_look_words_[static_cast<std::size_t>(r)];
    // kFirstLookWords: only the round's first look (the object before its learn pushes).
    if (!uses(ClaimSignal::kFirstLookWords) || words.sum() == 0) add_words(words, d);
  }

  static void add_words(Eigen::VectorXd& counts, const std::vector<std::int32_t>& d) {
    for (const std::int32_t w : d) counts[w] += 1.0;
  }

  // claims_by kDescriptors: `desc` added to class `r`'s descriptors, kept at descriptor_cap
  // (evenly spaced rows of all of them when over it).
  void add_descriptors(int r, const cv::Mat& desc) {
    if (desc.empty()) return;
    cv::Mat& mine = class_descriptors_[static_cast<std::size_t>(r)];
    cv::Mat all;
    if (mine.empty()) {
      all = desc.clone();
    } else {
      cv::vconcat(mine, desc, all);
    }
    mine = cap_rows(all, o_.descriptor_cap);
  }

  static cv::Mat cap_rows(const cv::Mat& all, int cap) {
    if (all.rows <= cap) return all;
    cv::Mat kept(cap, all.cols, all.type());
    for (int i = 0; i < cap; ++i) {
      const auto row = static_cast<int>(static_cast<std::int64_t>(i) * all.rows / cap);
      all.row(row).copyTo(kept.row(i));
    }
    return kept;
  }

  // One push: plan given, executed, logged. Returns whether the robot executed it.
  bool execute(PushIntent& intent, const std::string& episode) {
    attendant_.before_push(intent);
    robot::PushRecording rec;
    if (!episode.empty()) {
      rec.episode_dir = episodes_ / episode;
      rec.overwrite = true;
    }
    rec.fps = o_.fps;
    bool ok = true;
    std::string message;
    try {
      const robot::PushReport rep = robot_.push(intent.plan->push, rec);
      message = rep.message;
    } catch (const Error& e) {
      ok = false;
      message = e.what();
    }
    attendant_.after_push(intent, ok);
    log({.event = "push",
         .round = intent.round,
         .phase = intent.phase,
         .index = intent.index,
         .blob = intent.blob,
         .plan = LoggedPlan::of(*intent.plan),
         .executed = ok,
         .message = message,
         .episode = episode,
         .offset = offset_ != 0 ? std::optional<double>(offset_) : std::nullopt});
    offset_ = 0;
    if (!ok) {
      fault(intent.round, "robot-refused", message);
      extra_approach_ = std::min(kMaxExtraApproach, extra_approach_ + kApproachStep);
      log({.event = "replan",
           .round = intent.round,
           .why = "refused: approaches grow",
           .extra_approach = extra_approach_});
    }
    return ok;
  }

  planning::PushPlan plan(const planning::PlanningView& view, int blob, planning::PushGoal goal,
                          const Eigen::Vector2d& target) {
    robot::ArmState arm(robot_.arm());
    planning::PushPlanOptions po = plan_options_;
    // After a refusal (the hand would come down inside a tall object, whose features lie above
    // the table and make it look nearer than it is) approaches grow.
    po.max_approach = std::min(0.3, po.max_approach + extra_approach_);
    po.min_approach = std::min(po.max_approach, po.min_approach + extra_approach_);
    po.seed = core::stream_seed(o_.seed, kPlanStream, static_cast<std::uint64_t>(++plans_));
    planning::PushPlan p =
        planning::plan_push(view, blob, goal, target, region_, arm, robot_.joints(), po);
    if (p.outcome != planning::PlanOutcome::kPlanned && p.rejected_topple > 0 && !strict_topple_) {
      // topple_ratio: every push would tip the object over; pushed as without the check.
      const int rejected = p.rejected_topple;
      po.topple_ratio = 0;
      p = planning::plan_push(view, blob, goal, target, region_, arm, robot_.joints(), po);
      p.rejected_topple = rejected;
      p.message += " (every push would tip it over: planned without that check)";
    }
    return p;
  }

  // switch_tries: the blob of `view` other than `skip` whose least gap to the others (by the
  // robot's check: depth footprints with alone_by_depth, else the feature hulls) is largest; -1
  // when there is none.
  int most_isolated(const planning::PlanningView& view, int skip) const {
    DepthFootprints fp;
    if (o_.alone_by_depth && !view.depth.empty()) {
      fp = depth_footprints(view.depth, view.camera, region_);
    }
    int best = -1;
    double best_gap = -1;
    for (std::size_t k = 0; k < view.objects.size(); ++k) {
      if (static_cast<int>(k) == skip) continue;
      double g = std::numeric_limits<double>::infinity();
      std::optional<DepthAlone> d;
      if (!fp.parts.empty()) d = depth_alone(fp, view, static_cast<int>(k), o_.clearance);
      if (d && d->measured) {
        g = d->merged ? 0.0 : d->gap;
      } else {
        for (std::size_t j = 0; j < view.objects.size(); ++j) {
          if (j != k) g = std::min(g, hull_gap(view.objects[j].hull, view.objects[k].hull));
        }
      }
      if (g > best_gap) {
        best_gap = g;
        best = static_cast<int>(k);
      }
    }
    return best;
  }

  // The ground truth's singulation is scored after a round's (b) before (c) starts; a (b) run
  // again in (c) (crowded_reclears) is not scored, so that it cannot raise the figure.
  void note_cleared(int r, const planning::PlanningView& view, int blob) {
    if (!reclearing_) attendant_.cleared(r, view, blob);
  }

  // (b): push the blob nearest the chosen one toward the edge until every other is `clearance`
  // away. Returns the chosen blob's centre after it (nullopt: lost).
  std::optional<Eigen::Vector2d> clear(int r, Eigen::Vector2d chosen, int& index) {
    singulated_ = false;
    int pushes = 0;
    std::optional<Eigen::Vector2d> last_pushed;  // the pushed blob's centre before its push
    std::map<std::pair<double, double>, int> still_count;
    std::vector<Eigen::Vector2d> stuck;  // blobs that two pushes did not move: left alone
    int free_moves = 0;                  // free_space: pushes of the chosen object tried
    const auto still = [&](const Eigen::Vector2d& p) -> int& {
      return still_count[{std::round(p.x() / kStill), std::round(p.y() / kStill)}];
    };
    std::optional<planning::PlanningView> previous;  // merge_ratio: the look before
    int previous_blob = -1;
    while (true) {
      const planning::PlanningView view = look();
      const int c = track(view, chosen);
      if (c < 0) {
        fault(r, "lost", "the chosen object is no longer where it was (off the table or merged)");
        note_cleared(r, view, -1);
        return std::nullopt;
      }
      // merge_ratio: a clearing push pushed a neighbour into the chosen object (fewer blobs, its
      // blob grown): (c) would learn both as one, so the object counts as lost and the round
      // chooses again.
      if (o_.merge_ratio > 0 && previous &&
          merged_by_growth(*previous, previous_blob, view, c, o_.merge_ratio)) {
        fault(r, "grown",
              core::printf_string(
                  "(b): the look shows %d blobs (%d before) and the chosen object's blob %d of "
                  "%d feature points (%d before): merged with a neighbour, choosing again",
                  static_cast<int>(view.objects.size()), static_cast<int>(previous->objects.size()),
                  c, static_cast<int>(view.objects[static_cast<std::size_t>(c)].pixels.size()),
                  static_cast<int>(
                      previous->objects[static_cast<std::size_t>(previous_blob)].pixels.size())));
        note_cleared(r, view, -1);
        return std::nullopt;
      }
      if (o_.merge_ratio > 0) {
        previous = view;
        previous_blob = c;
      }
      chosen = view.objects[static_cast<std::size_t>(c)].centre;
      if (last_pushed) {
        const int same = track(view, *last_pushed);
        if (same >= 0 && same != c &&
            (view.objects[static_cast<std::size_t>(same)].centre - *last_pushed).norm() < kStill) {
          if (++still(*last_pushed) >= 2) {
            stuck.push_back(*last_pushed);
            fault(r, "moved-nothing",
                  "two pushes left a blob where it was (two objects seen as one?); left alone");
          } else {
            fault(r, "moved-nothing", "the last clearing push moved nothing; re-planning");
          }
        }
      }
      // The robot's check from depth footprints (logged whenever the camera measures depth;
      // alone_by_depth: it decides).
      std::optional<DepthAlone> by_depth;
      if (!view.depth.empty()) {
        by_depth =
            depth_alone(depth_footprints(view.depth, view.camera, region_), view, c, o_.clearance);
      }
      const bool use_depth = o_.alone_by_depth && by_depth && by_depth->measured;
      std::vector<std::pair<double, int>> others;
      int hull_near = 0;  // blobs too near by the feature hulls (logged beside the depth check)
      for (std::size_t k = 0; k < view.objects.size(); ++k) {
        if (static_cast<int>(k) == c) continue;
        const bool left_alone = std::any_of(stuck.begin(), stuck.end(), [&](const auto& p) {
          return (view.objects[k].centre - p).norm() < kStill;
        });
        if (left_alone) continue;
        double gap = hull_gap(view.objects[k].hull, view.objects[static_cast<std::size_t>(c)].hull);
        if (gap < o_.clearance) ++hull_near;
        if (use_depth && by_depth->blob_gaps[k]) gap = *by_depth->blob_gaps[k];
        if (gap < o_.clearance) others.emplace_back(gap, static_cast<int>(k));
      }
      std::sort(others.begin(), others.end());
      log({.event = "look",
           .round = r,
           .phase = "clear",
           .chosen = c,
           .too_near = static_cast<int>(others.size()),
           .gap = by_depth && by_depth->measured && std::isfinite(by_depth->gap)
                      ? std::optional<double>(by_depth->gap)
                      : std::nullopt,
           .why = by_depth ? std::optional<std::string>(
                                 core::cat({"feature hulls: ", std::to_string(hull_near),
                                            " too near; ", by_depth->why}))
                           : std::nullopt,
           .blobs = putative_object_records(view, false)});
      // alone_by_depth: not alone although no blob is too near (the chosen blob lies on two
      // footprints, or a footprint without a blob is too near): nothing this (b) can push.
      if (use_depth && !by_depth->alone && others.empty()) {
        fault(r, "cannot-clear",
              core::cat({"not alone by depth with no blob to push away (", by_depth->why, ")"}));
        note_cleared(r, view, c);
        return chosen;
      }
      if (others.empty()) {
        singulated_ = true;
        log({.event = "singulated", .round = r, .clear_pushes = pushes});
        note_cleared(r, view, c);
        return chosen;
      }
      if (pushes >= o_.clear_pushes) {
        fault(r, "not-singulated",
              core::cat({"gave up clearing after ", std::to_string(pushes), " pushes"}));
        note_cleared(r, view, c);
        return chosen;
      }
      // free_space: the chosen object itself into the room the others leave, first.
      if (o_.free_space > 0 && free_moves < kFreeMoves) {
        ++free_moves;
        if (to_free_space(r, view, c, others.front().first, chosen, index)) {
          ++pushes;
          last_pushed.reset();
          continue;
        }
      }
      bool pushed = false;
      bool refused = false;
      for (const auto& [gap, k] : others) {
        // Away from the chosen object, far enough to leave it alone (a kEdge push's direction
        // ignores the chosen object and often brought the other one nearer to it); kEdge when
        // that cannot be planned.
        const auto& other = view.objects[static_cast<std::size_t>(k)];
        const Eigen::Vector2d away = (other.centre - chosen).normalized();
        const double distance = std::clamp(o_.clearance - gap + kClearMargin, o_.plan.min_distance,
                                           o_.plan.max_distance);
        planning::PushPlan p =
            plan(view, k, planning::PushGoal::kTarget, other.centre + distance * away);
        if (p.outcome != planning::PlanOutcome::kPlanned) {
          p = plan(view, k, planning::PushGoal::kEdge, {});
        }
        if (p.outcome != planning::PlanOutcome::kPlanned) {
          log({.event = "plan",
               .round = r,
               .phase = "clear",
               .blob = k,
               .gap = gap,
               .plan = LoggedPlan::of(p)});
          continue;
        }
        PushIntent in{r, "clear", index++, &view, k, &p};
        ++pushes;
        if (execute(in, "")) {
          ++out_.pushes_clear;
          last_pushed = view.objects[static_cast<std::size_t>(k)].centre;
          pushed = true;
          break;
        }
        refused = true;
      }
      // A refusal (the hand would meet an object on its way down) grew the approaches: plan
      // again rather than give up clearing after one refusal (seed 1: 3 of 4 rounds did, and
      // their learn pushes then moved neighbours too).
      if (!pushed && refused && pushes < o_.clear_pushes) continue;
      if (!pushed) {
        fault(r, "cannot-clear", "no push of a nearby object could be planned or executed");
        note_cleared(r, view, c);
        return chosen;
      }
    }
  }

  // (b), free_space: push blob c of `view` (the chosen object, `gap` m from its nearest
  // neighbour) to the free spot that gives it kFreeGain more room, within free_space of the
  // work centre, whose corridor keeps clear of the others. Returns whether a push was executed;
  // `chosen` is then the object's centre after it (found by its motion).
  bool to_free_space(int r, const planning::PlanningView& view, int c, double gap,
                     Eigen::Vector2d& chosen, int& index) {
    const std::vector<FreeSpot> spots =
        free_spots(view, c, centre_, o_.free_space, kMaxFreePush, kFreeStep);
    int tried = 0;
    for (const FreeSpot& spot : spots) {
      if (spot.gap < gap + kFreeGain || tried >= kFreeTries) break;
      if ((spot.point - chosen).norm() < kFreeStep) continue;
      if (learn_push_lack(view, c, spot.point, kFreeCorridor) > 0) continue;
      ++tried;
      planning::PushPlan p = plan(view, c, planning::PushGoal::kTarget, spot.point);
      const std::string then = core::printf_string(
          "free space: the chosen object toward (%.3f, %.3f), least gap %.3f -> %.3f m",
          spot.point.x(), spot.point.y(), gap, spot.gap);
      log({.event = "plan",
           .round = r,
           .phase = "clear",
           .blob = c,
           .gap = gap,
           .plan = LoggedPlan::of(p),
           .then = then});
      if (p.outcome != planning::PlanOutcome::kPlanned) continue;
      const cv::Mat before_image = image_.clone();
      PushIntent in{r, "clear", index++, &view, c, &p};
      if (!execute(in, "")) return false;
      ++out_.pushes_clear;
      planning::PlanningView after = look();
      const int now = planning::find_pushed_object(before_image, image_, after,
                                                   view.objects[static_cast<std::size_t>(c)],
                                                   p.target, kFindRadius, region_, plan_options_);
      chosen = now >= 0 ? after.objects[static_cast<std::size_t>(now)].centre : p.target;
      return true;
    }
    return false;
  }

  // A learn push's episode and its M-L segmentation (kMotion), with the threshold of the scored
  // frame's mask, applied to every frame's painted map.
  struct Segmented {
    episode::Episode episode;
    segmentation::MlResult ml;
    double threshold = std::numeric_limits<double>::infinity();
    [[nodiscard]] bool valid() const {
      return ml.scored_frame >= 0 && !ml.frame_maps.empty() && std::isfinite(threshold) &&
             threshold > 0;
    }
  };
  Segmented segment(const fs::path& dir) {
    Segmented s{.episode = episode::read_episode(dir), .ml = {}};
    segmentation::MlOptions mo = o_.segmentation;
    mo.keep_frame_maps = true;
    s.ml = segmentation::segment_ml(s.episode, mo);
    if (s.ml.scored_frame < 0 || s.ml.frame_maps.empty()) return s;
    for (int v = 0; v < s.ml.mask.rows; ++v) {
      for (int u = 0; u < s.ml.mask.cols; ++u) {
        if (s.ml.mask(v, u) != 0) s.threshold = std::min(s.threshold, double{s.ml.map(v, u)});
      }
    }
    return s;
  }
  // Frame i's mask of what moved with the arm (valid() segmentations only); `arm` gets the
  // arm's own image when cut_arm or arm_patches_out needs it (else it is left empty).
  cv::Mat frame_mask(const Segmented& s, int i, cv::Mat* arm = nullptr) {
    cv::Mat m = s.ml.frame_maps[static_cast<std::size_t>(i)] >= s.threshold;
    // The arm moves with the arm: its own image (its kinematics at the frame's joints) is cut
    // out, as proprio learn does. Without this a view's mask lay a third on the arm (oracle
    // ladder, docs/results/selfsupervision-history.md).
    if (o_.cut_arm || o_.arm_patches_out) {
      const cv::Mat a = detail::arm_image_mask(s.episode, i, m.size(), robot_.arm(), arm_state_);
      if (o_.cut_arm) m.setTo(0, a);
      if (arm != nullptr) *arm = a;
    }
    return m;
  }

  // Whether the learn pushes' episodes are recorded and segmented (views motion or both).
  [[nodiscard]] bool motion_views() const { return o_.views != ViewSource::kBlob; }

  // views both: the look before the push (`image`, its view `view`) cut out by the pushed blob
  // `c`, added to the push's `docs` (its motion views) once a motion view, so that it weighs as
  // much as all of them; none (false) when the blob has too few features.
  bool add_before_view(const PushIntent& intent, const fs::path& dir, const cv::Mat& image,
                       const planning::PlanningView& view, int c,
                       std::vector<std::vector<std::int32_t>>& docs) {
    const cv::Mat mask = blob_mask(view.objects[static_cast<std::size_t>(c)], size_);
    const features::Features f = masked_features(image, mask, o_.features, o_.dilate);
    if (f.size() < o_.min_features) return false;
    const std::vector<std::int32_t> d = features::document_words(vocabulary_, image, f, colour_);
    const std::size_t copies = docs.size();
    for (std::size_t i = 0; i < copies; ++i) {
      docs.push_back(d);
      if (keep_view_descriptors()) view_descriptors_.push_back(f.descriptors);
      // Its truth: the episode's first frame (nothing pushed yet).
      attendant_.view_taken(intent, dir, 0, mask);
    }
    return true;
  }

  // views_of keeps its views' descriptors (own_model_rungs, descriptor_source views).
  [[nodiscard]] bool keep_view_descriptors() const {
    return o_.own_model_rungs || descriptors_from(DescriptorSource::kViews);
  }

  // The training views of one learn push's episode (kMotion; `seg` its segmentation when made
  // already) or of the look after it (kBlob).
  std::vector<std::vector<std::int32_t>> views_of(const PushIntent& intent, const fs::path& dir,
                                                  const planning::PlanningView& after, int blob,
                                                  cv::Mat& last_mask, SelfSupervisionDecision& what,
                                                  const Segmented* seg = nullptr) {
    std::vector<std::vector<std::int32_t>> docs;
    view_descriptors_.clear();
    if (o_.views == ViewSource::kBlob) {
      if (blob < 0) return docs;
      last_mask = blob_mask(after.objects[static_cast<std::size_t>(blob)], size_);
      features::Features f = masked_features(image_, last_mask, o_.features, o_.dilate);
      if (f.size() >= o_.min_features) {
        docs.push_back(features::document_words(vocabulary_, image_, f, colour_));
        if (keep_view_descriptors()) view_descriptors_.push_back(f.descriptors);
        attendant_.view_taken(intent, {}, -1, last_mask);
      }
      what.source = "blob";
      return docs;
    }
    std::optional<Segmented> own;
    if (seg == nullptr) own.emplace(segment(dir));
    const Segmented& sg = seg != nullptr ? *seg : *own;
    const episode::Episode& e = sg.episode;
    const segmentation::MlResult& ml = sg.ml;
    what.source = "motion";
    what.segmentation = ml.summary.message;
    if (!sg.valid()) return docs;
    const int first = ml.first_touch_frame.value_or(0);
    int used = 0;
    int small = 0;
    for (int i = first; i < static_cast<int>(ml.frame_maps.size()); i += o_.view_step) {
      cv::Mat arm;
      cv::Mat m = frame_mask(sg, i, &arm);
      if (cv::countNonZero(m) == 0) continue;
      const cv::Mat frame = e.frame(i);
      features::Features f =
          masked_features(frame, m, o_.features, o_.dilate, o_.arm_patches_out ? arm : cv::Mat());
      if (f.size() < o_.min_features) {
        ++small;
        continue;
      }
      docs.push_back(features::document_words(vocabulary_, frame, f, colour_));
      if (keep_view_descriptors()) view_descriptors_.push_back(f.descriptors);
      attendant_.view_taken(intent, dir, i, m);
      last_mask = m;
      ++used;
    }
    what.frames = e.frame_count();
    what.first_touch = first;
    what.views = used;
    what.too_few_features = small;
    return docs;
  }

  // (c): the planned learn push `p` of blob `c` made to turn the object (turning_push), when the
  // shifted push keeps clear of the others on the way down and is within reach.
  void turn(int r, const planning::PlanningView& view, int c, planning::PushPlan& p) {
    if (o_.turn_offset <= 0) return;
    const auto& hull = view.objects[static_cast<std::size_t>(c)].hull;
    const TurningPush t = turning_push(p, hull, o_.turn_offset);
    if (t.offset == 0) return;
    std::vector<std::vector<Eigen::Vector2d>> others;
    for (std::size_t k = 0; k < view.objects.size(); ++k) {
      if (static_cast<int>(k) != c) others.push_back(view.objects[k].hull);
    }
    robot::ArmState arm(robot_.arm());
    const robot::JointVector q = robot_.joints();
    const bool blocked =
        plan_options_.descent_clearance > 0 &&
        planning::descent_blocked(t.push.start, hull, others, plan_options_.descent_clearance);
    const bool reach =
        !blocked && robot::reachable(arm, t.push.start, t.push.height, q) &&
        robot::reachable(arm, t.push.start, t.push.height + robot::PushMotionOptions{}.lift, q) &&
        robot::reachable(arm, t.push.end, t.push.height, q);
    if (!reach) {
      log({.event = "plan",
           .round = r,
           .phase = "learn",
           .blob = c,
           .then = blocked ? "through the centre: the turning push's start is blocked"
                           : "through the centre: the turning push is out of reach"});
      return;
    }
    p.push = t.push;
    offset_ = t.offset;
  }

  // refind_colour: the blob of `view` that refind_by_colours takes for round r's object, by the
  // blobs' pixel colours and the rounds' looks'; -1: none. Logged either way (event "refound"
  // with the blob, or "refind" without).
  int refind_by_colour(int r, const planning::PlanningView& view) {
    std::vector<Eigen::VectorXd> blobs(view.objects.size());
    for (std::size_t k = 0; k < blobs.size(); ++k) {
      blobs[k] = blob_colours(view, static_cast<int>(k));
    }
    const std::vector<Eigen::VectorXd> others =
        refind_vetoes(r, class_look_colours_, merging() ? judge().judged : std::vector<int>());
    const ColourRefind f = refind_by_colours(
        blobs, class_look_colours_[static_cast<std::size_t>(r)], others, o_.refind_colour);
    if (f.blob >= 0) {
      log({.event = "refound",
           .round = r,
           .blob = f.blob,
           .why = core::printf_string(
               "colour: no blob where the object was; blob %d's pixel colours are %.3f "
               "(Hellinger) from the round's looks, the nearest of %d blobs",
               f.blob, f.distance, static_cast<int>(view.objects.size()))});
    } else {
      log({.event = "refind",
           .round = r,
           .why = f.nearest < 0
                      ? std::string("colour: no blob nearer the round's looks than others' looks")
                      : core::printf_string("colour: the nearest blob (%d) is %.3f (Hellinger) "
                                            "from the round's looks, not below %.3f",
                                            f.nearest, f.distance, o_.refind_colour)});
    }
    return f.blob;
  }

  // (c): which blob of `after` is round r's object (follow_by_looks on the blobs' looks).
  Followed follow(int r, const planning::PlanningView& after, int tracked) {
    BlobDocuments found = blob_documents(after);
    auto& docs = found.docs;
    const auto& rows = found.rows;
    std::vector<Eigen::VectorXd> blobs(after.objects.size());
    if (!docs.empty()) {
      const Eigen::MatrixXd th = theta_of(docs);
      for (std::size_t i = 0; i < rows.size(); ++i) {
        blobs[static_cast<std::size_t>(rows[i])] = th.row(static_cast<Eigen::Index>(i)).transpose();
      }
    }
    std::vector<std::vector<Eigen::VectorXd>> others;
    for (std::size_t q = 0; q < class_looks_.size(); ++q) {
      if (static_cast<int>(q) != r) others.push_back(class_looks_[q]);
    }
    return follow_by_looks(blobs, class_looks_[static_cast<std::size_t>(r)], others, tracked,
                           o_.refind_margin);
  }

  // split_by_motion: the push's motion segmentation `seg` splits `before` (the look before the
  // push, blob c planned) by its mask at the first touch and judges what moved from the episode
  // (episode_motion: `pushed`, `motion`), and splits `after` by its mask at the push's end.
  // Returns the pushed object's index in `after` (-1: not found there), or -2 when the
  // segmentation found nothing (the caller judges by the looks).
  int split_by_push(int r, const Segmented& seg, planning::PlanningView& before, int c,
                    planning::PlanningView& after, const Eigen::Vector2d& target, int& pushed,
                    PushMotion& motion) {
    if (!seg.valid()) return -2;
    const episode::Episode& e = seg.episode;
    const int n = std::min(e.frame_count(), static_cast<int>(seg.ml.frame_maps.size()));
    if (n < 2) return -2;
    const cv::Size size = seg.ml.frame_maps.front().size();
    if (size != before.image_size || size != after.image_size) return -2;
    const auto grow = [&](const cv::Mat& m) {
      return m.empty() ? m : features::dilated(m, o_.dilate);
    };
    // What moved with the arm at the first touch (where the object was) and at the end.
    cv::Mat touch;
    cv::Mat end;
    cv::Mat explained(size, CV_8U, cv::Scalar(0));
    for (int i = seg.ml.first_touch_frame.value_or(0); i < n; ++i) {
      const cv::Mat m = frame_mask(seg, i);
      if (cv::countNonZero(m) == 0) continue;
      if (touch.empty()) touch = m;
      end = m;
    }
    // No frame's mask holds anything: the segmentation found nothing, so nothing is split and
    // the push is judged by the looks (an empty touch mask would judge it moved nothing).
    if (touch.empty()) return -2;
    for (int i = 0; i < n; ++i) {
      cv::bitwise_or(explained, seg.ml.frame_maps[static_cast<std::size_t>(i)] >= seg.threshold,
                     explained);
    }
    for (const int i : {0, n - 1}) {
      cv::bitwise_or(explained, detail::arm_image_mask(e, i, size, robot_.arm(), arm_state_),
                     explained);
    }
    const std::size_t before_blobs = before.objects.size();
    const EpisodeMotion em =
        episode_motion(before, c, grow(touch), grow(explained), e.frame(0), e.frame(n - 1),
                       o_.moved_share, o_.min_features, region_, plan_options_);
    pushed = em.pushed;
    motion = em.motion;
    if (end.empty()) return -1;
    const std::size_t blobs = after.objects.size();
    const cv::Mat moved = grow(end);
    (void)planning::split_putative_objects(after, {moved}, o_.min_features, region_, plan_options_);
    // The pushed object: of the parts the end mask holds (min_features points or more), the
    // one nearest the push's target. (The part holding most of the mask, split's answer, was
    // a neighbour swept along as often: the round then went on with it, purity fell 82 -> 51%
    // on the tuning seed.)
    const int now = pushed_part(after, moved, target, o_.min_features);
    log({.event = "split",
         .round = r,
         .phase = "learn",
         .blob = now,
         .then = core::printf_string(
             "before the push: %d blobs -> %d (pushed blob %d -> %d); after: %d -> %d",
             static_cast<int>(before_blobs), static_cast<int>(before.objects.size()), c, pushed,
             static_cast<int>(blobs), static_cast<int>(after.objects.size()))});
    return now;
  }

  // (c): push the chosen object again and again from several sides, taking its views.
  // Returns true when (repeat_tries) the round's first views were already explained by a
  // learned class: the views were dropped and the round should choose again.
  bool learn(int r, Eigen::Vector2d chosen, int& index, core::ProgressBar& bar, int budget) {
    crowded_at_.reset();
    double angle = rng_.uniform(-std::numbers::pi, std::numbers::pi);
    // The circle of targets: about the work centre, or (free_space) about the object's place
    // after (b), kept within free_space of the work centre.
    Eigen::Vector2d hub = centre_;
    if (o_.free_space > 0) {
      const Eigen::Vector2d d = chosen - centre_;
      hub = d.norm() <= o_.free_space ? chosen : centre_ + (o_.free_space / d.norm()) * d;
      log({.event = "hub", .round = r, .work_centre = xy(hub)});
    }
    int done = 0;
    int attempts = 0;
    bool views_seen = false;  // repeat_later: a push of this call gave views
    // The look after the last executed push and the chosen object in it (found by its motion):
    // the next push plans on it instead of looking again and re-finding the object by position.
    std::optional<planning::PlanningView> carried;
    int carried_blob = -1;
    while (done < budget && attempts < 2 * budget + 4) {
      ++attempts;
      const planning::PlanningView view = carried ? std::move(*carried) : look();
      int c = carried ? carried_blob : track(view, chosen);
      carried.reset();
      if (c < 0 && view.objects.size() == 1) {
        // Singulated: the one blob in view is the object, wherever the push left it.
        c = 0;
        log({.event = "refound", .round = r, .why = "the only blob in view"});
      }
      if (c < 0 && o_.refind_colour > 0) c = refind_by_colour(r, view);
      if (c < 0) {
        fault(r, "lost", "the chosen object is no longer in view (off the table or out of reach)");
        out_.stop_reasons[static_cast<std::size_t>(r)] = "chosen object lost";
        break;
      }
      chosen = view.objects[static_cast<std::size_t>(c)].centre;
      keep_look(r, view, c);
      Eigen::Vector2d target =
          hub + o_.circle_radius * Eigen::Vector2d(std::cos(angle), std::sin(angle));
      angle += kGoldenAngle;
      if ((target - chosen).norm() < 0.03) {
        target = hub - (target - hub);
      }
      if ((target - chosen).norm() > kMaxLearnPush) {  // short pushes: it turns, stays in view
        target = chosen + kMaxLearnPush * (target - chosen).normalized();
      }
      // Out of reach from that side (an object far from the arm cannot be pushed toward it), or
      // its corridor toward a neighbour: the other sides, an eighth of a turn apart, pushed
      // kSidePush far, then (learn_clearance) kShortLearnPush far.
      const Eigen::Vector2d first = target - chosen;
      const double a0 = std::atan2(first.y(), first.x());
      const int lengths = o_.learn_clearance > 0 ? 2 : 1;
      planning::PushPlan p;
      p.outcome = planning::PlanOutcome::kUnreachable;
      p.message = "no side kept clear of the other blobs";
      bool crowded = false;  // a side was left out for its corridor
      std::vector<Eigen::Vector2d> goals{target};
      for (int l = 0; l < lengths; ++l) {
        for (const auto& g : fallback_goals(chosen, hub, a0, l == 0 ? kSidePush : kShortLearnPush,
                                            kSides, o_.circle_radius, o_.inward_sides)) {
          goals.push_back(g);
        }
        if (l == 0 && lengths > 1) {
          goals.push_back(chosen + kShortLearnPush * Eigen::Vector2d(std::cos(a0), std::sin(a0)));
        }
      }
      // topple_ratio: every side is first tried with pushes that would tip the object left out;
      // only when none is left is each tried again as without the check.
      const int passes = plan_options_.topple_ratio > 0 ? 2 : 1;
      for (int pass = 0; pass < passes && p.outcome != planning::PlanOutcome::kPlanned; ++pass) {
        strict_topple_ = pass + 1 < passes;
        for (const Eigen::Vector2d& goal : goals) {
          const double lack = learn_push_lack(view, c, goal, o_.learn_clearance);
          if (lack > 0) {
            crowded = true;
            log({.event = "plan",
                 .round = r,
                 .phase = "learn",
                 .blob = c,
                 .then = "another side: the corridor goes toward another blob",
                 .lack = lack});
            continue;
          }
          p = plan(view, c, planning::PushGoal::kTarget, goal);
          if (p.outcome == planning::PlanOutcome::kPlanned) {
            // The planner may move the target (the table's region): the corridor checked again.
            const double l2 = learn_push_lack(view, c, p.target, o_.learn_clearance);
            if (l2 <= 0) break;
            crowded = true;
            log({.event = "plan",
                 .round = r,
                 .phase = "learn",
                 .blob = c,
                 .plan = LoggedPlan::of(p),
                 .then = "another side: the corridor goes toward another blob",
                 .lack = l2});
            p.outcome = planning::PlanOutcome::kUnreachable;
            p.message = "no side kept clear of the other blobs";
            continue;
          }
          log({.event = "plan",
               .round = r,
               .phase = "learn",
               .blob = c,
               .plan = LoggedPlan::of(p),
               .then = "another side"});
        }
      }
      strict_topple_ = false;
      if (p.outcome != planning::PlanOutcome::kPlanned) {
        log({.event = "plan", .round = r, .phase = "learn", .blob = c, .plan = LoggedPlan::of(p)});
        if (crowded) {
          // Every side either toward a neighbour or not planned: pushing anyway would move the
          // neighbour and the round would drift to it.
          fault(r, "crowded", "no learn push keeps clear of the other blobs: the round stops");
          out_.stop_reasons[static_cast<std::size_t>(r)] =
              "no learn push keeps clear of the other blobs";
          crowded_at_ = chosen;
          break;
        }
        fault(r, "not-planned", core::cat({"no side could be pushed: ", p.message}));
        if (extra_approach_ > 0) extra_approach_ = 0;  // the grown approach may be to blame
        if (hub != centre_) {
          // free_space: no side of the object's place was within reach (session 19, seed 3: a
          // hub 10 cm beyond the work centre, 34 learn pushes not planned): the work centre's
          // circle again.
          hub = centre_;
          log({.event = "hub",
               .round = r,
               .why = "no learn push could be planned about the object's place",
               .work_centre = xy(hub)});
        }
        continue;
      }
      turn(r, view, c, p);
      const std::string name = core::printf_string("round%d-push%02d", r + 1, done + 1);
      PushIntent in{r, "learn", index++, &view, c, &p};
      if (!execute(in, motion_views() ? name : std::string())) continue;
      ++out_.pushes_learn;
      // Where is it now? What moved in the push near the plan's target (the hull carried there),
      // or (a push that moved nothing) where it was. The blob nearest the target was taken
      // before: with the others not cleared away (singulation failed in 90% of rounds) that
      // was often another object, and the round went on pushing it (seed 1: the learn pushes
      // of round 2 went to 4 blobs in turn; docs/results/selfsupervision-history.md, 2026-12-03).
      const cv::Mat before_image = image_.clone();
      planning::PlanningView after = look();
      // What the push moved: the blobs of the look before it whose features changed; or
      // (split_by_motion) the objects the push's own motion segmentation split them into, judged
      // by the episode's frames.
      planning::PlanningView judged = view;
      int pushed = c;
      std::optional<Segmented> seg;
      int split_now = -1;
      PushMotion motion;
      if (o_.split_by_motion && motion_views()) {
        seg = segment(episodes_ / name);
        split_now = split_by_push(r, *seg, judged, c, after, p.target, pushed, motion);
      }
      if (split_now < -1 || !seg || !seg->valid()) {
        motion = push_motion(before_image, image_, view, o_.moved_share, c);
      }
      int now = split_now >= 0
                    ? split_now
                    : planning::find_pushed_object(before_image, image_, after,
                                                   view.objects[static_cast<std::size_t>(c)],
                                                   p.target, kFindRadius, region_, plan_options_);
      if (now < 0) now = track(after, chosen);
      // A neighbour moved instead (or the object was two touching ones): the round's own looks
      // find the object again, and this push's views, of the neighbour, are not learned.
      bool swapped = false;
      if (o_.refind_margin > 0 && !class_looks_[static_cast<std::size_t>(r)].empty() &&
          !after.objects.empty()) {
        const Followed f = follow(r, after, now);
        if (f.refound) {
          log({.event = "refound",
               .round = r,
               .blob = f.blob,
               .why = core::printf_string(
                   "looks: blob %d matches the round's looks (Hellinger %.2f), the blob that "
                   "moved (%d) does not (%.2f)",
                   f.blob, f.distance, now, f.tracked_distance)});
          swapped = now >= 0;
          now = f.blob;
        }
      }
      if (now >= 0 &&
          (after.objects[static_cast<std::size_t>(now)].centre - chosen).norm() < kStill) {
        fault(r, "moved-nothing", "the push left the chosen object where it was");
      }
      if (o_.moved_colours && keeps_colours()) {
        const double n = add_moved_colours(r, before_image, view, c, after, now);
        log({.event = "colours",
             .round = r,
             .blob = now,
             .why = "the pixels the push moved, added to the round's colours",
             .moved_pixels = static_cast<int>(n)});
      }
      // On the looks' blobs: a fragment of the pushed object that its touch mask left out is a
      // part of `judged` of its own, and would count as merged with it.
      const int merged = merged_blob(view, c, after, now);
      log({.event = "motion",
           .round = r,
           .phase = "learn",
           .blob = pushed,
           .source = seg && seg->valid() && split_now >= -1 ? std::optional<std::string>("episode")
                                                            : std::nullopt,
           .shares = motion.share,
           .moved_most = motion.most,
           .merged_with = merged >= 0 ? std::optional<int>(merged) : std::nullopt});
      // The push moved a neighbour most: the round would go on with the neighbour as its object.
      const bool drift = o_.stop_on_drift && motion.most >= 0 && motion.most != pushed;
      // The object and another moved: the views would show both.
      const bool two = o_.alone_views && !drift && motion.most == pushed && !motion.alone(pushed);
      // merge_ratio: the push left the object and a neighbour one blob (as the robot sees it).
      const bool grown = o_.merge_ratio > 0 && !drift && !two &&
                         merged_by_growth(view, c, after, now, o_.merge_ratio);
      cv::Mat last_mask;
      SelfSupervisionDecision what;
      // A swap: this push's views would show the neighbour; none are taken.
      std::vector<std::vector<std::int32_t>> docs;
      if (drift) {
        fault(r, "drift",
              core::printf_string("the push moved blob %d most (%.2f of its features), not the "
                                  "round's object (blob %d, %.2f): no views, the round stops",
                                  motion.most, motion.share[static_cast<std::size_t>(motion.most)],
                                  pushed, motion.share[static_cast<std::size_t>(pushed)]));
      } else if (two) {
        fault(r, "two-moved",
              core::printf_string("the push moved %d blobs (the round's object and another): "
                                  "no views taken",
                                  static_cast<int>(motion.moved.size())));
      } else if (grown) {
        fault(r, "grown",
              core::printf_string(
                  "the look after the push shows %d blobs (%d before) and the object's blob %d "
                  "of %d feature points (%d before): merged with a neighbour, no views, the "
                  "round stops",
                  static_cast<int>(after.objects.size()), static_cast<int>(view.objects.size()),
                  now, static_cast<int>(after.objects[static_cast<std::size_t>(now)].pixels.size()),
                  static_cast<int>(view.objects[static_cast<std::size_t>(c)].pixels.size())));
      } else if (swapped) {
        fault(r, "swapped", "the push moved another object than the round's: no views taken");
      } else {
        docs = views_of(in, episodes_ / name, after, now, last_mask, what, seg ? &*seg : nullptr);
        if (o_.views == ViewSource::kBoth && !docs.empty() &&
            add_before_view(in, episodes_ / name, before_image, view, c, docs)) {
          what.source = "both";
          what.views = static_cast<int>(docs.size());
        }
      }
      if (repeat_check_ && !docs.empty()) {
        repeat_check_ = false;  // the round's first push with views only
        if (repeated(r, docs, after, now, true)) {
          attendant_.views_taken(in, 0, last_mask);
          ++done;
          if (done <= o_.pushes) bar.tick();
          return true;
        }
      } else if (o_.repeat_later && views_seen && !docs.empty() && !model_so_far_.objects.empty() &&
                 repeated(r, docs, after, now, false)) {
        // The round drifted onto a learned object: no views, the round stops.
        attendant_.views_taken(in, 0, last_mask);
        ++done;
        if (done <= o_.pushes) bar.tick();
        out_.stop_reasons[static_cast<std::size_t>(r)] =
            "a later push's views were explained by a learned class";
        break;
      }
      if (!docs.empty()) views_seen = true;
      attendant_.views_taken(in, static_cast<int>(docs.size()), last_mask);
      if (!docs.empty()) {
        const Eigen::MatrixXd th = theta_of(docs);
        auto& v = out_.views;
        const Eigen::Index n0 = v.theta.rows();
        v.theta.conservativeResize(n0 + th.rows(), th.cols());
        v.theta.bottomRows(th.rows()) = th;
        for (const auto& d : docs) {
          v.labels.push_back(r);
          v.push.push_back(done);
          v.tokens.push_back(static_cast<int>(d.size()));
          v.words.add_tokens(d);
        }
        if (keep_view_descriptors()) {
          // views_of's descriptors of exactly these documents (the only source of docs here).
          if (view_descriptors_.size() != docs.size()) {
            throw Error("selfsupervise: the views' descriptors do not match their documents");
          }
        }
        if (o_.own_model_rungs) {
          v.descriptors.insert(v.descriptors.end(), view_descriptors_.begin(),
                               view_descriptors_.end());
        }
        if (descriptors_from(DescriptorSource::kViews)) {
          for (const cv::Mat& d : view_descriptors_) add_descriptors(r, d);
        }
        out_.views_per_class[static_cast<std::size_t>(r)] += static_cast<int>(docs.size());
      }
      what.event = "views";
      what.round = r;
      what.push = done;
      what.taken = static_cast<int>(docs.size());
      log(std::move(what));
      if (now >= 0) {
        chosen = after.objects[static_cast<std::size_t>(now)].centre;
        carried = std::move(after);
        carried_blob = now;
      }
      ++done;
      if (done <= o_.pushes) bar.tick();
      if (drift) {
        out_.stop_reasons[static_cast<std::size_t>(r)] = "the push moved another object most";
        break;
      }
      if (grown) {
        out_.stop_reasons[static_cast<std::size_t>(r)] =
            "the push merged the object with a neighbour (its blob grew, fewer blobs)";
        break;
      }
      if (o_.stop_on_drift && merged >= 0) {
        fault(r, "merged",
              core::printf_string("the pushed blob now holds blob %d of the look before: the "
                                  "round stops",
                                  merged));
        out_.stop_reasons[static_cast<std::size_t>(r)] = "the pushed blob merged with another";
        break;
      }
    }
    if (done < o_.pushes) bar.tick(static_cast<std::size_t>(o_.pushes - done));
    if (done < budget) {
      if (out_.stop_reasons[static_cast<std::size_t>(r)].empty()) {
        out_.stop_reasons[static_cast<std::size_t>(r)] =
            core::cat({"only ", std::to_string(done), " pushes succeeded"});
      }
    }
    return false;
  }

  // repeat_tries (`first`): whether a learned class already explains this round's first views
  // (`docs`); if so the round's looks of its object (and the look after the push, blob `now` of
  // `after`) go to that class, so that (d) sees the object as learned, and the views are not
  // kept. repeat_later (not `first`): the same test of a later push's views; if so only the look
  // after the push goes to that class (the round's earlier looks are of its own object).
  bool repeated(int r, const std::vector<std::vector<std::int32_t>>& docs,
                const planning::PlanningView& after, int now, bool first) {
    std::vector<int> labels;
    labels.reserve(out_.views.labels.size());
    for (const int l : out_.views.labels) {
      const auto it = std::find(model_class_.begin(), model_class_.end(), l);
      labels.push_back(it == model_class_.end() ? -1 : static_cast<int>(it - model_class_.begin()));
    }
    const RepeatTest t =
        explained_by(model_so_far_, out_.views.theta, labels, theta_of(docs), o_.repeat_share);
    std::string shares;
    for (std::size_t m = 0; m < t.shares.size(); ++m) {
      shares += core::printf_string(
          "%s%s %.2f", m ? ", " : "",
          out_.class_names[static_cast<std::size_t>(model_class_[m])].c_str(), t.shares[m]);
    }
    const char* which = first ? "the round's first views" : "a later push's views";
    if (t.cls < 0) {
      log({.event = "repeat",
           .round = r,
           .why = core::cat({which, " are new (shares explained: ", shares, ")"}),
           .views = static_cast<int>(docs.size())});
      return false;
    }
    const int c = model_class_[static_cast<std::size_t>(t.cls)];
    auto& mine = class_looks_[static_cast<std::size_t>(r)];
    auto& theirs = class_looks_[static_cast<std::size_t>(c)];
    auto& mine_words = class_look_words_[static_cast<std::size_t>(r)];
    auto& their_words = class_look_words_[static_cast<std::size_t>(c)];
    auto& mine_colours = class_look_colours_[static_cast<std::size_t>(r)];
    auto& their_colours = class_look_colours_[static_cast<std::size_t>(c)];
    if (first) {
      theirs.insert(theirs.end(), mine.begin(), mine.end());
      mine.clear();
      their_words += mine_words;
      mine_words.setZero();
      their_colours += mine_colours;
      mine_colours.setZero();
      auto& mine_list = class_look_colour_list_[static_cast<std::size_t>(r)];
      auto& their_list = class_look_colour_list_[static_cast<std::size_t>(c)];
      their_list.insert(their_list.end(), mine_list.begin(), mine_list.end());
      mine_list.clear();
      add_descriptors(c, class_descriptors_[static_cast<std::size_t>(r)]);
      class_descriptors_[static_cast<std::size_t>(r)] = cv::Mat();
    }
    if (now >= 0) {
      cv::Mat desc;
      const auto d = blob_document(after, now, descriptors_from_looks() ? &desc : nullptr);
      if (!descriptors_from(DescriptorSource::kFirstLook) ||
          class_descriptors_[static_cast<std::size_t>(c)].empty()) {
        add_descriptors(c, desc);
      }
      if (!d.empty()) {
        theirs.push_back(theta_of({d}).row(0).transpose());
        if (!uses(ClaimSignal::kFirstLookWords) || their_words.sum() == 0) {
          add_words(their_words, d);
        }
        if (keeps_colours() && !o_.moved_colours &&
            (!o_.colour_first_look || their_colours.sum() <= 0)) {
          const Eigen::VectorXd look = blob_colours(after, now);
          their_colours += look;
          if (o_.colour_by_look && look.sum() > 0) {
            class_look_colour_list_[static_cast<std::size_t>(c)].push_back(look / look.sum());
          }
        }
      }
    }
    log({.event = "repeat",
         .round = r,
         .why =
             core::cat({which, " are explained by ", out_.class_names[static_cast<std::size_t>(c)],
                        " (shares explained: ", shares,
                        first ? "): views dropped, its looks given to that class, choose again"
                              : "): views dropped, the look after the push given to that "
                                "class, the round stops"}),
         .views = static_cast<int>(docs.size())});
    return true;
  }

  void round(int r, core::ProgressBar& bar) {
    extra_approach_ = 0;
    round_ = r;
    const planning::PlanningView view = look();
    log({.event = "look",
         .round = r,
         .phase = "choose",
         .blobs = putative_object_records(view, false)});
    if (!episodes_.empty()) {
      cv::Mat img = image_.clone();
      for (const auto& o : view.objects) cv::rectangle(img, o.box, cv::Scalar(255, 255, 0), 1);
      cv::imwrite((episodes_ / core::printf_string("round%d-look.png", r + 1)).string(), img);
    }
    if (view.objects.empty()) {
      fault(r, "no-blobs", "no putative object in view; round skipped");
      out_.stop_reasons[static_cast<std::size_t>(r)] = "no blobs";
      bar.tick(static_cast<std::size_t>(o_.pushes));
      return;
    }
    if (static_cast<int>(view.objects.size()) < objects_) {
      fault(r, "fewer-blobs",
            core::cat({std::to_string(view.objects.size()), " blobs for ", std::to_string(objects_),
                       " objects: some are merged or out of view; going on with what is seen"}));
    }
    const int k = choose(r, view);
    attendant_.chose(r, view, k);
    int index = 0;
    std::optional<Eigen::Vector2d> chosen =
        clear(r, view.objects[static_cast<std::size_t>(k)].centre, index);
    // Lost while clearing (pushed along or merged with a neighbour): choose again from a new
    // look rather than end the round with nothing learned (the next round then chose the same
    // object again, as no look of it was kept: seed 2 chose the bike in 3 of 4 rounds).
    for (int again = 0; !chosen && again < kRechoices; ++again) {
      const planning::PlanningView now = look();
      if (now.objects.empty()) break;
      log({.event = "look",
           .round = r,
           .phase = "choose",
           .why = "the chosen object was lost while clearing: choosing again",
           .blobs = putative_object_records(now, false)});
      const int k2 = choose(r, now);
      attendant_.chose(r, now, k2);
      chosen = clear(r, now.objects[static_cast<std::size_t>(k2)].centre, index);
    }
    // singulate_tries: (c) starts only on an object the robot's own check finds alone, (b)
    // started again a bounded number of times.
    for (int t = 0; chosen && !singulated_ && t < o_.singulate_tries; ++t) {
      log({.event = "replan",
           .round = r,
           .why = core::cat({"(b) ended with the chosen object not alone: (b) again, try ",
                             std::to_string(t + 1), " of ", std::to_string(o_.singulate_tries)})});
      chosen = clear(r, *chosen, index);
    }
    if (chosen && !singulated_ && o_.singulate_tries > 0) {
      log({.event = "replan",
           .round = r,
           .why = "(b) tried again as often as allowed and the object is still not alone: (c) "
                  "starts on it anyway"});
    }
    // switch_tries: another object, the one standing farthest from the others by the robot's
    // check, when (b) could not singulate this one.
    for (int t = 0; chosen && !singulated_ && t < o_.switch_tries; ++t) {
      const planning::PlanningView now = look();
      const int k2 = most_isolated(now, track(now, *chosen));
      if (k2 < 0) break;
      log({.event = "replan",
           .round = r,
           .blob = k2,
           .why = core::cat({"(b) could not singulate the chosen object: the blob farthest from "
                             "the others chosen instead, switch ",
                             std::to_string(t + 1), " of ", std::to_string(o_.switch_tries)}),
           .blobs = putative_object_records(now, false)});
      attendant_.chose(r, now, k2);
      chosen = clear(r, now.objects[static_cast<std::size_t>(k2)].centre, index);
    }
    // recheck_tries: the chosen blob, after (b), is a learned class's: choose again.
    if (chosen && o_.recheck_tries > 0) chosen = recheck(r, *chosen, index);
    if (!chosen) {
      out_.stop_reasons[static_cast<std::size_t>(r)] = "chosen object lost while clearing";
      bar.tick(static_cast<std::size_t>(o_.pushes));
      return;
    }
    // (c) follows its object by the pushes' motion; a look there with fewer blobs than C has
    // mostly lost an object off the table, and splitting its largest blob, often the object
    // learned, made most learn pushes unplannable (tuning seed 1): no splits in (c).
    // Unspent pushes of earlier rounds (objects lost, pushes not planned) go to this one.
    int budget = o_.carry_budget ? round_budget(r, o_.pushes, out_.pushes_learn) : o_.pushes;
    int reclears = 0;
    for (int t = 0;; ++t) {
      splitting_ = false;
      repeat_check_ = t < o_.repeat_tries && !model_so_far_.objects.empty();
      const int spent = out_.pushes_learn;
      const bool again = learn(r, *chosen, index, bar, budget);
      repeat_check_ = false;
      splitting_ = true;
      if (!again) {
        // crowded_reclears: (c) stopped because every learn push would sweep its object toward a
        // neighbour (the singulated object drifted back among the others): (b) again about where
        // it is, then (c) goes on with the pushes left.
        budget -= out_.pushes_learn - spent;
        if (!crowded_at_ || reclears >= o_.crowded_reclears || budget <= 0) break;
        ++reclears;
        log({.event = "replan",
             .round = r,
             .why = core::cat({"(c) stopped crowded: (b) again about the object, then (c) with ",
                               std::to_string(budget), " pushes left, re-clear ",
                               std::to_string(reclears), " of ",
                               std::to_string(o_.crowded_reclears)})});
        reclearing_ = true;
        chosen = clear(r, *crowded_at_, index);
        reclearing_ = false;
        if (!chosen) {
          out_.stop_reasons[static_cast<std::size_t>(r)] =
              "crowded in (c), and the object was lost while clearing again";
          break;
        }
        out_.stop_reasons[static_cast<std::size_t>(r)].clear();
        continue;
      }
      // repeat_tries: the object was learned already; another, with the pushes left.
      budget -= out_.pushes_learn - spent;
      const planning::PlanningView now = look();
      log({.event = "look",
           .round = r,
           .phase = "choose",
           .why = "the round's object was learned already: choosing again",
           .blobs = putative_object_records(now, false)});
      if (now.objects.empty() || budget <= 0) {
        out_.stop_reasons[static_cast<std::size_t>(r)] =
            "the round's object was learned already and no other could be chosen";
        break;
      }
      const int k2 = choose(r, now);
      attendant_.chose(r, now, k2);
      chosen = clear(r, now.objects[static_cast<std::size_t>(k2)].centre, index);
      if (!chosen) {
        out_.stop_reasons[static_cast<std::size_t>(r)] =
            "the round's object was learned already and the next was lost while clearing";
        break;
      }
    }
    refit();
  }

  // The classes learned so far (for (d)'s choice).
  void refit() {
    std::vector<int> labels = out_.views.labels;
    std::vector<std::string> names;
    std::vector<int> remap(static_cast<std::size_t>(out_.classes), -1);
    for (int c = 0; c < out_.classes; ++c) {
      if (out_.views_per_class[static_cast<std::size_t>(c)] >= 2) {
        remap[static_cast<std::size_t>(c)] = static_cast<int>(names.size());
        names.push_back(out_.class_names[static_cast<std::size_t>(c)]);
      }
    }
    if (names.empty()) return;
    for (int& l : labels) l = l < 0 ? -1 : remap[static_cast<std::size_t>(l)];
    model_so_far_ = topics::fit_mot(out_.views.theta, labels, names, o_.mot).model;
    model_class_.clear();
    for (int c = 0; c < out_.classes; ++c) {
      if (remap[static_cast<std::size_t>(c)] >= 0) model_class_.push_back(c);
    }
  }

  void fit() {
    refit();
    out_.model = model_so_far_;
    out_.model_class = model_class_;
    for (int c = 0; c < out_.classes; ++c) {
      if (out_.views_per_class[static_cast<std::size_t>(c)] < 2) {
        fault(c, "class-dropped",
              core::cat({out_.class_names[static_cast<std::size_t>(c)], " has ",
                         std::to_string(out_.views_per_class[static_cast<std::size_t>(c)]),
                         " views (a Dirichlet needs 2); left out of the model"}));
      }
    }
  }

  // SelfSupervisionOptions::rounds: more rounds than objects, merged by the robot's judgement.
  [[nodiscard]] bool merging() const { return out_.classes > objects_; }

  // Per round run so far: its views' word counts.
  std::vector<Eigen::VectorXd> round_counts() const {
    std::vector<Eigen::VectorXd> counts(static_cast<std::size_t>(rounds_run_),
                                        Eigen::VectorXd::Zero(words_));
    for (std::size_t d = 0; d < out_.views.labels.size(); ++d) {
      const int r = out_.views.labels[d];
      if (r < 0 || r >= rounds_run_) continue;
      const topics::DocumentView doc = out_.views.words.document(d);
      for (std::size_t k = 0; k < doc.size(); ++k) {
        counts[static_cast<std::size_t>(r)][doc.words[k]] += doc.counts[k];
      }
    }
    return counts;
  }

  // The robot's judgement so far: the round classes grouped (merge_rounds at same_object on
  // their views' words, or at same_colour on their looks' colours).
  RoundMerge judge() const { return judge(judged_counts(round_counts())); }
  // The judgement from the judged counts (judged_counts), counted once by the caller.
  RoundMerge judge(const std::vector<Eigen::VectorXd>& counts) const {
    if (counts.empty()) return {};
    return by_colour() ? merge_rounds(counts, objects_, o_.same_colour, colour_round_distance)
                       : merge_rounds(counts, objects_, o_.same_object);
  }

  // Per round run so far: the counts the judgement compares (its views' words, or its looks'
  // colours). A round without views takes no part either way (zero counts): it learned no class.
  // `words`: round_counts().
  [[nodiscard]] std::vector<Eigen::VectorXd> judged_counts(
      const std::vector<Eigen::VectorXd>& words) const {
    if (!by_colour()) return words;
    std::vector<Eigen::VectorXd> colours(words.size(), Eigen::VectorXd::Zero(o_.colour.count()));
    for (std::size_t r = 0; r < words.size() && r < class_look_colours_.size(); ++r) {
      if (words[r].sum() > 0) colours[r] = class_look_colours_[r];
    }
    return colours;
  }

  // After a round: whether the robot judges C distinct objects learned (logged either way).
  bool judged_done() {
    const RoundMerge m = judge();
    const bool done = m.distinct >= objects_;
    log({.event = "judge",
         .round = rounds_run_ - 1,
         .why = core::cat({std::to_string(m.distinct), " distinct objects of ",
                           std::to_string(objects_), " judged from ", std::to_string(rounds_run_),
                           " rounds (round classes nearer than ",
                           by_colour() ? core::printf_string("%.3g", o_.same_colour)
                                       : core::printf_string("%.3g", o_.same_object),
                           by_colour() ? " (Hellinger, their looks' colours)" : " nats a word",
                           " are one object): ",
                           done ? "every object learned, no more rounds"
                                : "another round, choosing the object least like the groups"}),
         .classes = m.distinct});
    return done;
  }

  // The round classes merged into C classes (merge_rounds), every merge logged; the views
  // relabelled, the classes renamed object_1..object_C.
  void merge_into_classes() {
    // The rounds' view words, counted once for the judgement and the diagnostics below.
    const auto words = round_counts();
    const auto counts = judged_counts(words);
    const RoundMerge m = judge(counts);
    // Every pair of rounds with views: their distance (what the merges below were made from).
    const RoundDistance distance = by_colour() ? colour_round_distance : round_distance;
    // Beside the judgement's signal, the others' distances (a diagnostic: which signal tells one
    // object's rounds from two objects').
    const auto colour_words = [&](std::size_t r) -> Eigen::VectorXd {
      const Eigen::Index n = words_ - static_cast<Eigen::Index>(vocabulary_.size());
      return words[r].tail(std::max<Eigen::Index>(n, 0));
    };
    const auto maybe = [](RoundDistance f, const Eigen::VectorXd& x,
                          const Eigen::VectorXd& y) -> std::optional<double> {
      if (x.size() == 0 || x.size() != y.size() || x.sum() <= 0 || y.sum() <= 0) return {};
      return f(x, y);
    };
    for (std::size_t a = 0; a < counts.size(); ++a) {
      for (std::size_t b = a + 1; b < counts.size(); ++b) {
        if (counts[a].sum() <= 0 || counts[b].sum() <= 0) continue;
        log({.event = "distance",
             .distance = distance(counts[a], counts[b]),
             .merged = std::vector<int>{static_cast<int>(a), static_cast<int>(b)},
             .word_distance = maybe(round_distance, words[a], words[b]),
             .view_colour_distance = maybe(round_distance, colour_words(a), colour_words(b)),
             .look_colour_distance =
                 keeps_colours()
                     ? maybe(colour_round_distance, class_look_colours_[a], class_look_colours_[b])
                     : std::nullopt});
      }
    }
    // The merges that made the classes: the first (rounds with views - C) of m.steps (the later
    // ones only group rounds for the judgement).
    const auto with_views = static_cast<int>(
        std::count_if(counts.begin(), counts.end(), [](const auto& c) { return c.sum() > 0; }));
    const auto applied = static_cast<std::size_t>(std::max(0, with_views - objects_));
    const char* bound = by_colour() ? "same_colour" : "same_object";
    for (std::size_t k = 0; k < applied && k < m.steps.size(); ++k) {
      const RoundMergeStep& st = m.steps[k];
      std::vector<int> both = st.a;
      both.insert(both.end(), st.b.begin(), st.b.end());
      std::sort(both.begin(), both.end());
      const auto list = [](const std::vector<int>& rs) {
        std::string t;
        for (const int r : rs) t += core::cat({t.empty() ? "" : "+", std::to_string(r + 1)});
        return t;
      };
      log({.event = "merge",
           .why = core::cat({"rounds ", list(st.a), " and ", list(st.b), ": ",
                             st.same ? core::cat({"nearer than ", bound, ": one object"})
                                     : core::cat({"not nearer than ", bound,
                                                  ", merged as more groups are left than C"})}),
           .distance = st.distance,
           .merged = both});
    }
    std::vector<int> cls = m.class_of_round;
    cls.resize(static_cast<std::size_t>(rounds_run_), -1);
    const int groups = cls.empty() ? 0 : *std::max_element(cls.begin(), cls.end()) + 1;
    for (std::size_t r = 0; r < cls.size(); ++r) {
      log({.event = "merge",
           .round = static_cast<int>(r),
           .why = cls[r] < 0 ? std::string("the round has no views: no class")
                             : core::cat({"round ", std::to_string(r + 1), " is object_",
                                          std::to_string(cls[r] + 1)})});
    }
    if (groups < objects_) {
      fault(rounds_run_ - 1, "fewer-classes",
            core::cat({std::to_string(groups), " classes of views for ", std::to_string(objects_),
                       " objects"}));
    }
    for (int& l : out_.views.labels) l = cls[static_cast<std::size_t>(l)];
    out_.views_per_class.assign(static_cast<std::size_t>(objects_), 0);
    for (const int l : out_.views.labels) {
      if (l >= 0) ++out_.views_per_class[static_cast<std::size_t>(l)];
    }
    out_.classes = objects_;
    out_.class_names.clear();
    for (int c = 0; c < objects_; ++c) {
      out_.class_names.push_back(core::cat({"object_", std::to_string(c + 1)}));
    }
    out_.round_class = cls;
    class_looks_.assign(static_cast<std::size_t>(objects_), {});
    class_look_words_.assign(static_cast<std::size_t>(objects_), Eigen::VectorXd::Zero(words_));
    class_look_colours_.assign(static_cast<std::size_t>(objects_),
                               Eigen::VectorXd::Zero(o_.colour.count()));
    class_look_colour_list_.assign(static_cast<std::size_t>(objects_), {});
    class_descriptors_.assign(static_cast<std::size_t>(objects_), cv::Mat());
  }

  robot::Robot& robot_;
  TableAttendant& attendant_;
  const topics::LdaModel& model_;
  const features::Vocabulary& vocabulary_;
  const SelfSupervisionOptions& o_;
  fs::path episodes_;
  core::Rng rng_;
  /// o_.colour_words: the colour words of every document made here, or none.
  std::optional<features::ColourWordOptions> colour_;
  int words_ = 0;  ///< the documents' words: the vocabulary's (+ the colour words)
  std::ofstream log_file_;
  planning::TableRegion region_;            ///< the planner's default: the table top
  planning::PushPlanOptions plan_options_;  ///< o_.plan scaled to the image
  Eigen::Vector2d centre_ = Eigen::Vector2d::Zero();
  cv::Size size_;
  cv::Mat image_;
  std::vector<bool> table_words_;  ///< table_colours_out: the last look's table colour words
  /// own_model_rungs: the descriptors of the documents views_of() returned last.
  std::vector<cv::Mat> view_descriptors_;
  Learning out_;
  topics::MotModel model_so_far_;
  std::vector<int> model_class_;
  /// Per class: thetas of its object's blob in the looks of its learn round ((d), kLooks).
  std::vector<std::vector<Eigen::VectorXd>> class_looks_;
  /// Per class: the word counts of the same looks (claims_by kLookWords).
  std::vector<Eigen::VectorXd> class_look_words_;
  /// Per class: the descriptors of the same looks, at most descriptor_cap (claims_by
  /// kDescriptors, or other_claims_by).
  std::vector<cv::Mat> class_descriptors_;
  /// Per class: its looks' pixels' colour-word counts (claims_by kColour, or other_claims_by).
  std::vector<Eigen::VectorXd> class_look_colours_;
  /// colour_by_look: per class, each of its looks' colour distribution (normalised).
  std::vector<std::vector<Eigen::VectorXd>> class_look_colour_list_;
  int plans_ = 0;
  bool repeat_check_ = false;  ///< repeat_tries: test the next push's views (learn)
  bool splitting_ = true;      ///< split_merged: looks of (a), (b) and (d) only, not of (c)
  bool singulated_ = false;    ///< the last clear() ended with the chosen object alone
  bool reclearing_ = false;    ///< crowded_reclears: a (b) within (c), not scored
  std::optional<Eigen::Vector2d> crowded_at_;  ///< learn() stopped crowded with its object here
  int round_ = 0;       ///< the round under way (for the looks' "split" events)
  int objects_ = 0;     ///< C, the objects on the table (out_.classes: the rounds)
  int rounds_run_ = 0;  ///< rounds run so far
  double offset_ = 0;   ///< the next push's turning offset, m (0: through the centre)
  /// topple_ratio: plan() leaves a plan whose every push would tip the object unplanned (the
  /// learn pushes' first pass over the sides); false: it re-plans it without the check.
  bool strict_topple_ = false;
  double extra_approach_ = 0;                 ///< m, grown after each refusal of the round
  std::optional<robot::ArmState> arm_state_;  ///< the arm's kinematics, for the arm's image
};

}  // namespace

void SelfSupervisionOptions::validate() const {
  core::check_field_bounds(*this, "selfsupervise");
  (void)parse_object_list(objects);
  features.validate();
  plan.validate();
  segmentation.validate();
  mot.validate();
  if (merge_ratio != 0.0 && merge_ratio <= 1.0) {
    throw Error("selfsupervise: merge_ratio must be 0 (off) or above 1");
  }
  if (crowded_reclears > 0 && learn_clearance <= 0) {
    throw Error(
        "selfsupervise: crowded_reclears needs learn_clearance (only its rounds stop crowded)");
  }
  if (recheck_tries > 0 && choice != NextObjectRule::kLooks) {
    throw Error("selfsupervise: recheck_tries needs choice looks (the learned classes' claims)");
  }
  if (claims_by == ClaimSignal::kNone) {
    throw Error("selfsupervise: claims_by none is not a claim signal");
  }
  if (same_object_by == RoundSimilarity::kColour && rounds == 0) {
    throw Error(
        "selfsupervise: same_object_by colour judges the rounds of --rounds: it needs rounds "
        "above 0");
  }
  if (claims_by == ClaimSignal::kColour || other_claims_by == ClaimSignal::kColour ||
      refind_colour > 0 || same_object_by == RoundSimilarity::kColour) {
    colour.validate();
  } else if (colour_first_look || moved_colours) {
    throw Error(core::cat(
        {"selfsupervise: ", colour_first_look ? "colour_first_look" : "moved_colours",
         " chooses the pixels of claims by colour, of refind_colour or of same_object_by colour: "
         "it needs one of them"}));
  }
  if (colour_by_look && (claims_by != ClaimSignal::kColour || colour_first_look || moved_colours)) {
    throw Error(
        "selfsupervise: colour_by_look compares a blob with each look of a class in the claims by "
        "colour: it needs claims_by colour, and not colour_first_look or moved_colours");
  }
  if (table_colours_out &&
      ((claims_by != ClaimSignal::kColour && other_claims_by != ClaimSignal::kColour) ||
       moved_colours)) {
    throw Error(
        "selfsupervise: table_colours_out leaves the table's colours out of the blobs' colours of "
        "the claims by colour: it needs claims by colour, and not moved_colours");
  }
  if (colour_first_look && moved_colours) {
    throw Error(
        "selfsupervise: colour_first_look and moved_colours are two sources of a round's colours: "
        "choose one");
  }
  if (colour_words) {
    colour.validate();
    if (oracle_ladder || own_model_rungs || ceiling_only) {
      throw Error(
          "selfsupervise: colour words do not go with the oracle ladder, its ceiling or the "
          "own-model rungs (their documents are SIFT words only)");
    }
  }
  if (mot_classifier == MotClassifier::kColour && !colour_words) {
    throw Error(
        "selfsupervise: mot_classifier colour scores by the colour words alone: it needs "
        "colour_words (--colour-words)");
  }
  // The default (kColour) goes with either choice; another signal is asked for, and only choice
  // looks makes claims.
  if (claims_by != ClaimSignal::kColour && choice != NextObjectRule::kLooks) {
    throw Error(
        core::cat({"selfsupervise: claims_by ", core::choice_name(claims_by, kClaimSignalNames),
                   " needs choice looks (the learned classes' claims)"}));
  }
  if (other_claims_by != ClaimSignal::kNone) {
    if (choice != NextObjectRule::kLooks) {
      throw Error(
          "selfsupervise: other_claims_by needs choice looks (the learned classes' claims)");
    }
    if (other_claims_by == claims_by) {
      throw Error("selfsupervise: other_claims_by must be another signal than claims_by");
    }
    const auto words = [](ClaimSignal s) {
      return s == ClaimSignal::kLookWords || s == ClaimSignal::kFirstLookWords;
    };
    if (words(claims_by) && words(other_claims_by)) {
      throw Error(
          "selfsupervise: other_claims_by look-words and first-look-words keep the same counts: "
          "not with each other");
    }
  }
}

std::vector<std::string> parse_object_list(const std::string& list) {
  std::vector<std::string> out;
  std::size_t b = 0;
  while (b <= list.size()) {
    std::size_t e = list.find(',', b);
    if (e == std::string::npos) e = list.size();
    std::string name = list.substr(b, e - b);
    const auto l = name.find_first_not_of(" \t");
    const auto r = name.find_last_not_of(" \t");
    name = l == std::string::npos ? std::string() : name.substr(l, r - l + 1);
    if (name.empty()) throw Error("objects: an empty object name in '" + list + "'");
    if (std::find(out.begin(), out.end(), name) != out.end()) {
      throw Error("objects: '" + name + "' is named twice");
    }
    out.push_back(name);
    b = e + 1;
  }
  return out;
}

features::Features masked_features(const cv::Mat& image, const cv::Mat& mask,
                                   const features::ExtractOptions& options, int dilate,
                                   const cv::Mat& exclude) {
  // A new matrix: `mask` is the caller's and stays as it was (dilating into a header that
  // shared its data grew the caller's mask by `dilate` px at every call, until session 28).
  cv::Mat m = features::dilated(mask, dilate);
  if (!exclude.empty() && cv::countNonZero(exclude) > 0) {
    if (exclude.size() != mask.size() || exclude.type() != CV_8U) {
      throw Error("masked_document: the exclude mask is not CV_8U of the mask's size");
    }
    // A grid point's patch reaches `exclude` exactly when the point lies in `exclude` grown by
    // the patch's half side (a square: the patch is one); features lie on the rounded point.
    const int half = static_cast<int>(std::ceil(options.dense.size / 2));
    cv::Mat reach;
    cv::dilate(exclude, reach,
               cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * half + 1, 2 * half + 1)));
    m.setTo(0, reach);
  }
  return features::extract_features(image, options, m);
}

cv::Mat masked_descriptors(const cv::Mat& image, const cv::Mat& mask,
                           const features::ExtractOptions& options, int dilate,
                           const cv::Mat& exclude) {
  features::Features f = masked_features(image, mask, options, dilate, exclude);
  if (f.size() == 0) return {};
  return f.descriptors;
}

std::vector<std::int32_t> masked_document(
    const cv::Mat& image, const cv::Mat& mask, const features::Vocabulary& vocabulary,
    const features::ExtractOptions& options, int dilate, const cv::Mat& exclude,
    const std::optional<features::ColourWordOptions>& colour) {
  return features::document_words(vocabulary, image,
                                  masked_features(image, mask, options, dilate, exclude), colour);
}

double hull_gap(const std::vector<Eigen::Vector2d>& a, const std::vector<Eigen::Vector2d>& b) {
  if (a.empty() || b.empty()) return std::numeric_limits<double>::infinity();
  if ((a.size() >= 3 && inside(a, b[0])) || (b.size() >= 3 && inside(b, a[0]))) return 0;
  double d = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Eigen::Vector2d& a0 = a[i];
    const Eigen::Vector2d& a1 = a[(i + 1) % a.size()];
    for (std::size_t j = 0; j < b.size(); ++j) {
      const Eigen::Vector2d& b0 = b[j];
      const Eigen::Vector2d& b1 = b[(j + 1) % b.size()];
      d = std::min({d, point_segment(a0, b0, b1), point_segment(b0, a0, a1)});
    }
  }
  // Crossing edges (overlap without a vertex inside) give a small but non-zero d here; that
  // case is the vertex test above for convex hulls, except for crosses: check them.
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Eigen::Vector2d& p = a[i];
    const Eigen::Vector2d r = a[(i + 1) % a.size()] - p;
    for (std::size_t j = 0; j < b.size(); ++j) {
      const Eigen::Vector2d& q = b[j];
      const Eigen::Vector2d s = b[(j + 1) % b.size()] - q;
      const double den = r.x() * s.y() - r.y() * s.x();
      if (std::abs(den) < 1e-15) continue;
      const Eigen::Vector2d qp = q - p;
      const double t = (qp.x() * s.y() - qp.y() * s.x()) / den;
      const double u = (qp.x() * r.y() - qp.y() * r.x()) / den;
      if (t >= 0 && t <= 1 && u >= 0 && u <= 1) return 0;
    }
  }
  return d;
}

std::vector<FreeSpot> free_spots(const planning::PlanningView& view, int blob,
                                 const Eigen::Vector2d& centre, double radius, double reach,
                                 double step) {
  ensure(blob >= 0 && blob < static_cast<int>(view.objects.size()),
         "free_spots: the blob is not one of the view's");
  ensure(step > 0 && radius >= 0 && reach >= 0, "free_spots: bad step, radius or reach");
  const auto& o = view.objects[static_cast<std::size_t>(blob)];
  std::vector<std::vector<Eigen::Vector2d>> others;
  for (std::size_t k = 0; k < view.objects.size(); ++k) {
    if (static_cast<int>(k) != blob && !view.objects[k].hull.empty()) {
      others.push_back(view.objects[k].hull);
    }
  }
  const auto gap_at = [&](const Eigen::Vector2d& p) {
    std::vector<Eigen::Vector2d> moved = o.hull;
    for (Eigen::Vector2d& h : moved) h += p - o.centre;
    double g = std::numeric_limits<double>::infinity();
    for (const auto& h : others) g = std::min(g, hull_gap(moved, h));
    return g;
  };
  std::vector<FreeSpot> out;
  if (others.empty()) return {{o.centre, std::numeric_limits<double>::infinity()}};
  const int n = static_cast<int>(std::floor(radius / step));
  for (int i = -n; i <= n; ++i) {
    for (int j = -n; j <= n; ++j) {
      const Eigen::Vector2d p =
          centre + step * Eigen::Vector2d(static_cast<double>(i), static_cast<double>(j));
      if ((p - centre).norm() > radius + 1e-12 || (p - o.centre).norm() > reach + 1e-12) continue;
      out.push_back({p, gap_at(p)});
    }
  }
  // Gaps in whole mm (a strict weak order), then the distance to the blob.
  const auto mm = [](double g) { return std::floor(g / 0.001); };
  std::stable_sort(out.begin(), out.end(), [&](const FreeSpot& a, const FreeSpot& b) {
    if (mm(a.gap) != mm(b.gap)) return mm(a.gap) > mm(b.gap);
    return (a.point - o.centre).norm() < (b.point - o.centre).norm();
  });
  return out;
}

std::vector<int> split_merged_blobs(planning::PlanningView& view, const cv::Mat& image, int classes,
                                    int min_features, double colour_weight,
                                    const planning::TableRegion& region,
                                    const planning::PushPlanOptions& options) {
  require(classes >= 1, "split_merged_blobs: classes must be at least 1");
  require(min_features >= 1, "split_merged_blobs: min_features must be at least 1");
  require(std::isfinite(colour_weight) && colour_weight >= 0,
          "split_merged_blobs: colour_weight must be finite and at least 0");
  require(image.type() == CV_8UC3 && image.size() == view.image_size,
          "split_merged_blobs: image must be 8-bit BGR of the view's image size");
  std::vector<int> split;
  if (static_cast<int>(view.objects.size()) >= classes) return split;
  cv::Mat lab;
  cv::cvtColor(image, lab, cv::COLOR_BGR2Lab);
  cv::blur(lab, lab, cv::Size(5, 5));
  const cv::Rect frame(cv::Point(0, 0), view.image_size);
  // Index into view.objects -> its index before any split (parts appended get -1: not split again).
  std::vector<int> original(view.objects.size());
  for (std::size_t i = 0; i < original.size(); ++i) original[i] = static_cast<int>(i);
  std::vector<char> tried(view.objects.size(), 0);
  const auto least = static_cast<std::size_t>(kSplitLeast) * static_cast<std::size_t>(min_features);
  while (static_cast<int>(view.objects.size()) < classes) {
    int b = -1;
    std::size_t most = 0;
    for (std::size_t i = 0; i < view.objects.size(); ++i) {
      const std::size_t n = view.objects[i].pixels.size();
      if (tried[i] == 0 && n >= least && n > most) {
        most = n;
        b = static_cast<int>(i);
      }
    }
    if (b < 0) break;
    tried[static_cast<std::size_t>(b)] = 1;
    const planning::PutativeObject& o = view.objects[static_cast<std::size_t>(b)];
    std::vector<cv::Point> pts;
    for (const Eigen::Vector2d& p : o.pixels) {
      const cv::Point q(static_cast<int>(std::lround(p.x())), static_cast<int>(std::lround(p.y())));
      if (frame.contains(q)) pts.push_back(q);
    }
    const auto n = static_cast<int>(pts.size());
    if (n < kSplitLeast * min_features) continue;
    // Standardised positions and colours; the start: the halves across the principal axis.
    Eigen::MatrixXd pos(n, 2);
    Eigen::MatrixXd col(n, 3);
    for (int i = 0; i < n; ++i) {
      const auto& q = pts[static_cast<std::size_t>(i)];
      pos.row(i) << q.x, q.y;
      const cv::Vec3b c = lab.at<cv::Vec3b>(q);
      col.row(i) << c[0], c[1], c[2];
    }
    pos.rowwise() -= pos.colwise().mean();
    col.rowwise() -= col.colwise().mean();
    const double sp = std::sqrt(pos.squaredNorm() / n);
    const double sc = std::sqrt(col.squaredNorm() / n);
    if (sp <= 0) continue;
    const Eigen::Matrix2d cov = pos.transpose() * pos / n;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov);
    const Eigen::Vector2d axis = eig.eigenvectors().col(1);
    cv::Mat samples(n, 5, CV_32F);
    cv::Mat labels(n, 1, CV_32S);
    for (int i = 0; i < n; ++i) {
      samples.at<float>(i, 0) = static_cast<float>(pos(i, 0) / sp);
      samples.at<float>(i, 1) = static_cast<float>(pos(i, 1) / sp);
      for (int k = 0; k < 3; ++k) {
        samples.at<float>(i, 2 + k) =
            sc > 0 ? static_cast<float>(colour_weight * col(i, k) / sc) : 0.0F;
      }
      labels.at<int>(i) = pos.row(i).dot(axis) < 0 ? 0 : 1;
    }
    cv::Mat centres;
    cv::kmeans(samples, 2, labels,
               cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 50, 1e-4), 1,
               cv::KMEANS_USE_INITIAL_LABELS, centres);
    // Each part's region: the blob's mask pixels nearest one of its points.
    std::vector<cv::Mat> regions(2, cv::Mat(view.image_size, CV_8U, cv::Scalar(0)));
    regions[1] = cv::Mat(view.image_size, CV_8U, cv::Scalar(0));
    for (int y = 0; y < o.mask.rows; ++y) {
      for (int x = 0; x < o.mask.cols; ++x) {
        if (o.mask(y, x) == 0) continue;
        const cv::Point q(x + o.box.x, y + o.box.y);
        int best = 0;
        int best_d = std::numeric_limits<int>::max();
        for (int i = 0; i < n; ++i) {
          const cv::Point d = pts[static_cast<std::size_t>(i)] - q;
          const int d2 = d.x * d.x + d.y * d.y;
          if (d2 < best_d) {
            best_d = d2;
            best = labels.at<int>(i);
          }
        }
        regions[static_cast<std::size_t>(best)].at<uchar>(q) = 255;
      }
    }
    const std::size_t before = view.objects.size();
    (void)planning::split_putative_objects(view, regions, min_features, region, options);
    if (view.objects.size() > before) {
      split.push_back(original[static_cast<std::size_t>(b)]);
      original.resize(view.objects.size(), -1);
      // The parts are not split again in this look (a third object would need its own look).
      tried.resize(view.objects.size(), 1);
    }
  }
  return split;
}

TurningPush turning_push(const planning::PushPlan& plan, const std::vector<Eigen::Vector2d>& hull,
                         double fraction) {
  TurningPush out{plan.push, 0.0};
  if (fraction == 0 || hull.size() < 3) return out;
  const Eigen::Vector2d n = plan.direction.normalized();
  // Negative fractions: to the right of n (counter-clockwise turns).
  const Eigen::Vector2d l = (fraction < 0 ? -1.0 : 1.0) * Eigen::Vector2d(-n.y(), n.x());
  double w = 0;
  for (const Eigen::Vector2d& h : hull) w = std::max(w, (h - plan.centre).dot(l));
  const double e = std::min(std::abs(fraction) * w, kMaxTurnOffset);
  if (e <= 0) return out;
  const Eigen::Vector2d contact = plan.centre + e * l;
  const double depth = planning::distance_to_hull_edge(hull, contact, -n);
  out.push.start = contact - (depth + plan.approach) * n;
  out.push.end = plan.push.end + e * l;
  // The pusher must still move forward along n past its start (a short push stays a push).
  if ((out.push.end - out.push.start).dot(n) <= 0.005) return {plan.push, 0.0};
  out.offset = fraction < 0 ? -e : e;
  return out;
}

double learn_push_lack(const planning::PlanningView& view, int blob, const Eigen::Vector2d& target,
                       double clearance) {
  ensure(blob >= 0 && blob < static_cast<int>(view.objects.size()),
         "learn_push_lack: the blob is not one of the view's");
  if (clearance <= 0) return 0.0;
  std::vector<std::vector<Eigen::Vector2d>> others;
  for (std::size_t k = 0; k < view.objects.size(); ++k) {
    if (static_cast<int>(k) != blob && !view.objects[k].hull.empty()) {
      others.push_back(view.objects[k].hull);
    }
  }
  const auto& o = view.objects[static_cast<std::size_t>(blob)];
  if (o.hull.empty()) return 0.0;
  // The pusher's own path is the planner's business (descent_clearance): hand_clearance 0.
  return planning::path_clearance(robot::TablePush{}, o.hull, o.centre, target, others, clearance,
                                  0.0);
}

namespace {

// The next blob's moved share s into m (push_motion, episode_motion): it moved at `threshold` or
// more; `best` is the largest share so far, whose blob is m.most.
void add_share(PushMotion& m, double s, double threshold, double& best) {
  const auto k = static_cast<int>(m.share.size());
  m.share.push_back(s);
  if (s >= threshold) {
    m.moved.push_back(k);
    if (s > best) {
      best = s;
      m.most = k;
    }
  }
}

// The tie rule: the pushed blob moved most when its share is within kShareTie of the largest
// (a share saturates at 1 for a blob pushed a few cm).
void prefer_pushed(PushMotion& m, int pushed, double threshold, double best) {
  if (pushed < 0 || pushed >= static_cast<int>(m.share.size()) || m.most < 0) return;
  const double own = m.share[static_cast<std::size_t>(pushed)];
  if (own >= threshold && own >= best - kShareTie) m.most = pushed;
}

}  // namespace

PushMotion push_motion(const cv::Mat& before, const cv::Mat& after,
                       const planning::PlanningView& view, double threshold, int pushed) {
  PushMotion m;
  double best = -1;
  for (const planning::PutativeObject& o : view.objects)
    add_share(m, planning::moved_share(before, after, o), threshold, best);
  prefer_pushed(m, pushed, threshold, best);
  return m;
}

std::vector<Eigen::Vector2d> fallback_goals(const Eigen::Vector2d& chosen,
                                            const Eigen::Vector2d& centre, double a0, double length,
                                            int sides, double radius, bool inward) {
  ensure(sides >= 1 && length > 0, "fallback_goals: bad sides or length");
  std::vector<Eigen::Vector2d> out;
  const double limit = std::max((chosen - centre).norm(), radius);
  for (int k = 1; k < sides; ++k) {
    const double a = a0 + (k * 2 * std::numbers::pi / sides);
    const Eigen::Vector2d g = chosen + length * Eigen::Vector2d(std::cos(a), std::sin(a));
    if (inward && (g - centre).norm() > limit) continue;
    out.push_back(g);
  }
  if (inward) {
    std::stable_sort(out.begin(), out.end(),
                     [&](const Eigen::Vector2d& x, const Eigen::Vector2d& y) {
                       return (x - centre).norm() < (y - centre).norm();
                     });
  }
  return out;
}

int pushed_part(const planning::PlanningView& view, const cv::Mat& mask,
                const Eigen::Vector2d& target, int min_features) {
  ensure(mask.type() == CV_8U && mask.size() == view.image_size,
         "pushed_part: the mask must be 8-bit of the view's image size");
  const cv::Rect image(cv::Point(0, 0), mask.size());
  int best = -1;
  double nearest = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < view.objects.size(); ++k) {
    int n = 0;
    for (const auto& p : view.objects[k].pixels) {
      const cv::Point q(static_cast<int>(std::lround(p.x())), static_cast<int>(std::lround(p.y())));
      if (image.contains(q) && mask.at<std::uint8_t>(q) != 0) ++n;
    }
    const double d = (view.objects[k].centre - target).norm();
    if (n >= min_features && d < nearest) {
      nearest = d;
      best = static_cast<int>(k);
    }
  }
  return best;
}

EpisodeMotion episode_motion(planning::PlanningView& view, int pushed, const cv::Mat& touch,
                             const cv::Mat& explained, const cv::Mat& first, const cv::Mat& last,
                             double threshold, int min_features,
                             const planning::TableRegion& region,
                             const planning::PushPlanOptions& options) {
  ensure(pushed >= 0 && pushed < static_cast<int>(view.objects.size()),
         "episode_motion: the pushed blob is not one of the view's");
  ensure(explained.empty() || (explained.type() == CV_8U && explained.size() == first.size()),
         "episode_motion: the explained mask must be 8-bit of the frames' size");
  EpisodeMotion out;
  out.pushed = pushed;
  if (!touch.empty()) {
    const std::vector<int> found =
        planning::split_putative_objects(view, {touch}, min_features, region, options);
    if (found[0] >= 0) out.pushed = found[0];
  }
  const cv::Rect image(cv::Point(0, 0), first.size());
  PushMotion& m = out.motion;
  double best = -1;
  for (std::size_t k = 0; k < view.objects.size(); ++k) {
    double s = 0;
    if (static_cast<int>(k) == out.pushed || explained.empty()) {
      s = planning::moved_share(first, last, view.objects[k]);
    } else {
      // Only the points the pushed object's own motion (and the arm) leave unexplained.
      planning::PutativeObject rest = view.objects[k];
      rest.pixels.clear();
      for (const auto& p : view.objects[k].pixels) {
        const cv::Point q(static_cast<int>(std::lround(p.x())),
                          static_cast<int>(std::lround(p.y())));
        if (image.contains(q) && explained.at<std::uint8_t>(q) == 0) rest.pixels.push_back(p);
      }
      s = rest.pixels.empty() ? 0.0 : planning::moved_share(first, last, rest);
    }
    add_share(m, s, threshold, best);
  }
  prefer_pushed(m, out.pushed, threshold, best);
  return out;
}

int merged_blob(const planning::PlanningView& before, int pushed,
                const planning::PlanningView& after, int now) {
  if (now < 0 || now >= static_cast<int>(after.objects.size())) return -1;
  const auto& hull = after.objects[static_cast<std::size_t>(now)].hull;
  if (hull.size() < 3) return -1;
  for (std::size_t k = 0; k < before.objects.size(); ++k) {
    if (static_cast<int>(k) != pushed && inside(hull, before.objects[k].centre)) {
      return static_cast<int>(k);
    }
  }
  return -1;
}

bool merged_by_growth(const planning::PlanningView& before, int pushed,
                      const planning::PlanningView& after, int now, double ratio) {
  require(std::isfinite(ratio) && ratio > 1.0, "merged_by_growth: ratio must be above 1");
  if (pushed < 0 || pushed >= static_cast<int>(before.objects.size())) return false;
  if (now < 0 || now >= static_cast<int>(after.objects.size())) return false;
  if (after.objects.size() >= before.objects.size()) return false;
  const auto was =
      static_cast<double>(before.objects[static_cast<std::size_t>(pushed)].pixels.size());
  const auto is = static_cast<double>(after.objects[static_cast<std::size_t>(now)].pixels.size());
  return was > 0 && is >= ratio * was;
}

int round_budget(int round, int pushes, int spent) {
  const int left = (round + 1) * pushes - spent;
  return std::clamp(left, 0, 2 * pushes);
}

Followed follow_by_looks(const std::vector<Eigen::VectorXd>& blobs,
                         const std::vector<Eigen::VectorXd>& own,
                         const std::vector<std::vector<Eigen::VectorXd>>& others, int tracked,
                         double margin) {
  Followed out;
  out.blob = tracked;
  const auto least = [](const Eigen::VectorXd& t, const std::vector<Eigen::VectorXd>& looks) {
    double d = std::numeric_limits<double>::infinity();
    for (const Eigen::VectorXd& e : looks) d = std::min(d, hellinger(t, e));
    return d;
  };
  const int n = static_cast<int>(blobs.size());
  const bool scored_tracked =
      tracked >= 0 && tracked < n && blobs[static_cast<std::size_t>(tracked)].size() > 0;
  if (!own.empty() && scored_tracked) {
    out.tracked_distance = least(blobs[static_cast<std::size_t>(tracked)], own);
    out.distance = out.tracked_distance;
  }
  if (margin <= 0 || own.empty()) return out;
  int best = -1;
  double best_d = std::numeric_limits<double>::infinity();
  for (int b = 0; b < n; ++b) {
    const Eigen::VectorXd& t = blobs[static_cast<std::size_t>(b)];
    if (t.size() == 0 || b == tracked) continue;
    const double d = least(t, own);
    double other = std::numeric_limits<double>::infinity();
    for (const auto& looks : others) other = std::min(other, least(t, looks));
    if (d < other && d < best_d) {
      best_d = d;
      best = b;
    }
  }
  if (best < 0) return out;
  if (scored_tracked && !(best_d + margin < out.tracked_distance)) return out;
  if (!scored_tracked && tracked >= 0) return out;  // moved but unscored: trust the motion
  out.blob = best;
  out.refound = true;
  out.distance = best_d;
  return out;
}

double hellinger(const Eigen::VectorXd& p, const Eigen::VectorXd& q) {
  ensure(p.size() == q.size(), "hellinger: distributions of different lengths");
  const double bc = (p.array().max(0.0) * q.array().max(0.0)).sqrt().sum();
  return std::sqrt(std::max(0.0, 1.0 - bc));
}

std::vector<Eigen::VectorXd> refind_vetoes(int round, const std::vector<Eigen::VectorXd>& colours,
                                           const std::vector<int>& judged) {
  const auto group = [&](int q) {
    return q >= 0 && q < static_cast<int>(judged.size()) ? judged[static_cast<std::size_t>(q)] : -1;
  };
  std::vector<Eigen::VectorXd> out;
  for (int q = 0; q < static_cast<int>(colours.size()); ++q) {
    if (q == round || (group(round) >= 0 && group(q) == group(round))) continue;
    out.push_back(colours[static_cast<std::size_t>(q)]);
  }
  return out;
}

ColourRefind refind_by_colours(const std::vector<Eigen::VectorXd>& blobs,
                               const Eigen::VectorXd& own,
                               const std::vector<Eigen::VectorXd>& others, double max_distance) {
  const auto normalised = [](const Eigen::VectorXd& n) -> std::optional<Eigen::VectorXd> {
    if (n.size() == 0 || !n.allFinite() || n.minCoeff() < 0 || n.sum() <= 0) return std::nullopt;
    return Eigen::VectorXd(n / n.sum());
  };
  ColourRefind out;
  const auto mine = normalised(own);
  if (!mine || max_distance <= 0) return out;
  std::vector<Eigen::VectorXd> theirs;
  for (const Eigen::VectorXd& o : others) {
    if (auto t = normalised(o); t && t->size() == mine->size()) theirs.push_back(*t);
  }
  for (std::size_t k = 0; k < blobs.size(); ++k) {
    const auto p = normalised(blobs[k]);
    if (!p || p->size() != mine->size()) continue;
    const double d = hellinger(*p, *mine);
    // Nearer another round's looks than this round's: that round's object, not this one.
    const bool other = std::any_of(theirs.begin(), theirs.end(),
                                   [&](const Eigen::VectorXd& t) { return hellinger(*p, t) < d; });
    if (!other && (out.nearest < 0 || d < out.distance)) {
      out.nearest = static_cast<int>(k);
      out.distance = d;
    }
  }
  if (out.nearest >= 0 && out.distance < max_distance) out.blob = out.nearest;
  return out;
}

namespace {
// Two rounds' counts checked for a distance (`what`: the function, `unit`: what is counted):
// one length, finite, non-negative, and something counted in each.
void check_round_counts(const Eigen::VectorXd& a, const Eigen::VectorXd& b, const char* what,
                        const char* unit) {
  if (a.size() != b.size() || a.size() == 0) {
    throw Error(core::cat({what, ": ", unit, " counts of different lengths (or none)"}));
  }
  if (!a.allFinite() || !b.allFinite() || a.minCoeff() < 0 || b.minCoeff() < 0) {
    throw Error(core::cat({what, ": ", unit, " counts must be finite and non-negative"}));
  }
  if (a.sum() <= 0 || b.sum() <= 0) {
    throw Error(core::cat({what, ": a round without ", unit, "s"}));
  }
}
}  // namespace

double round_distance(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  check_round_counts(a, b, "round_distance", "word");
  const double sa = a.sum();
  const double sb = b.sum();
  const auto n = static_cast<double>(a.size());
  const Eigen::ArrayXd la = ((a.array() + kRoundSmoothing) / (sa + kRoundSmoothing * n)).log();
  const Eigen::ArrayXd lb = ((b.array() + kRoundSmoothing) / (sb + kRoundSmoothing * n)).log();
  // H(a, phi_b) - H(a, phi_a) = sum_w a_w (log phi_a - log phi_b) / sum a.
  const double ab = (a.array() * (la - lb)).sum() / sa;
  const double ba = (b.array() * (lb - la)).sum() / sb;
  return std::max(0.0, 0.5 * (ab + ba));
}

double colour_round_distance(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  check_round_counts(a, b, "colour_round_distance", "colour");
  return hellinger(a / a.sum(), b / b.sum());
}

std::vector<bool> table_colour_words(const cv::Mat& image, const planning::PlanningView& view,
                                     const features::ColourWordOptions& colour, double share) {
  if (!(share > 0 && share <= 1)) throw Error("table_colour_words: share must be in (0, 1]");
  if (image.empty()) throw Error("table_colour_words: an empty image");
  cv::Mat outside(image.size(), CV_8U, cv::Scalar(255));
  for (const planning::PutativeObject& o : view.objects) {
    outside.setTo(0, blob_mask(o, image.size()));
  }
  const std::vector<double> counts = features::colour_word_counts(image, outside, colour);
  double all = 0;
  for (const double c : counts) all += c;
  std::vector<bool> table(counts.size(), false);
  if (all <= 0) return table;
  for (std::size_t w = 0; w < counts.size(); ++w) table[w] = counts[w] >= share * all;
  return table;
}

Eigen::VectorXd without_table_colours(const Eigen::VectorXd& counts,
                                      const std::vector<bool>& table) {
  if (static_cast<std::size_t>(counts.size()) != table.size()) {
    throw Error(core::cat({"without_table_colours: ", std::to_string(counts.size()),
                           " colour counts for ", std::to_string(table.size()), " flags"}));
  }
  Eigen::VectorXd out = counts;
  for (Eigen::Index w = 0; w < out.size(); ++w) {
    if (table[static_cast<std::size_t>(w)]) out[w] = 0;
  }
  return out.sum() > 0 ? out : counts;
}

cv::Mat moved_pixels(const cv::Mat& before, const cv::Mat& after, const cv::Mat& region,
                     int levels) {
  if (before.empty() || after.empty() || region.empty()) {
    throw Error("moved_pixels: an empty image or region");
  }
  if ((before.type() != CV_8UC3 && before.type() != CV_8UC1) || after.type() != before.type() ||
      region.type() != CV_8UC1) {
    throw Error("moved_pixels: the images must be both 8-bit BGR or grey, and the region 8-bit");
  }
  if (before.size() != after.size() || region.size() != before.size()) {
    throw Error("moved_pixels: the images and the region differ in size");
  }
  if (levels < 0 || levels >= 255) throw Error("moved_pixels: levels must be in [0, 255)");
  cv::Mat diff;
  cv::absdiff(before, after, diff);
  std::vector<cv::Mat> channels;
  cv::split(diff, channels);
  cv::Mat most = channels.front();
  for (const cv::Mat& ch : channels) most = cv::max(most, ch);
  cv::Mat moved = most > levels;
  moved.setTo(0, region == 0);
  return moved;
}

RoundMerge merge_rounds(const std::vector<Eigen::VectorXd>& counts, int classes, double same_object,
                        RoundDistance distance) {
  if (classes < 1) throw Error("merge_rounds: classes must be >= 1");
  if (distance == nullptr) throw Error("merge_rounds: no distance");
  struct Group {
    std::vector<int> rounds;
    Eigen::VectorXd counts;
  };
  std::vector<Group> groups;  // ordered by their first round
  for (std::size_t r = 0; r < counts.size(); ++r) {
    if (counts[r].size() != counts.front().size()) {
      throw Error("merge_rounds: word counts of different lengths");
    }
    if (counts[r].sum() > 0) groups.push_back({{static_cast<int>(r)}, counts[r]});
  }
  RoundMerge out;
  out.class_of_round.assign(counts.size(), -1);
  out.judged.assign(counts.size(), -1);
  const auto number = [&groups](std::vector<int>& dst) {
    for (std::size_t g = 0; g < groups.size(); ++g) {
      for (const int r : groups[g].rounds) dst[static_cast<std::size_t>(r)] = static_cast<int>(g);
    }
  };
  const auto many = [&groups] { return static_cast<int>(groups.size()); };
  if (many() <= classes) number(out.class_of_round);
  bool judging = true;
  while (groups.size() > 1) {
    std::size_t bi = 0;
    std::size_t bj = 1;
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < groups.size(); ++i) {
      for (std::size_t j = i + 1; j < groups.size(); ++j) {
        const double d = distance(groups[i].counts, groups[j].counts);
        if (d < best) {
          best = d;
          bi = i;
          bj = j;
        }
      }
    }
    const bool same = best < same_object;
    if (judging && !same) {
      number(out.judged);
      out.distinct = many();
      judging = false;
    }
    if (!judging && many() <= classes) break;
    out.steps.push_back({groups[bi].rounds, groups[bj].rounds, best, same});
    Group& g = groups[bi];
    g.rounds.insert(g.rounds.end(), groups[bj].rounds.begin(), groups[bj].rounds.end());
    std::sort(g.rounds.begin(), g.rounds.end());
    g.counts += groups[bj].counts;
    groups.erase(groups.begin() + static_cast<std::ptrdiff_t>(bj));
    if (many() == classes) number(out.class_of_round);
  }
  if (judging) {
    number(out.judged);
    out.distinct = many();
  }
  return out;
}

RepeatTest explained_by(const topics::MotModel& model, const Eigen::MatrixXd& known,
                        const std::vector<int>& known_labels, const Eigen::MatrixXd& fresh,
                        double share) {
  const int k = static_cast<int>(model.objects.size());
  if (static_cast<Eigen::Index>(known_labels.size()) != known.rows()) {
    throw Error("explained_by: one label per known view is needed");
  }
  if (!(share > 0 && share <= 1)) throw Error("explained_by: share must be in (0, 1]");
  if (known.rows() > 0 && fresh.rows() > 0 && known.cols() != fresh.cols()) {
    throw Error("explained_by: the known and fresh views' theta differ in length");
  }
  for (const int l : known_labels) {
    if (l < -1 || l >= k) throw Error("explained_by: a label is not a class of the model");
  }
  RepeatTest out;
  out.shares.assign(static_cast<std::size_t>(k), 0.0);
  out.floors.assign(static_cast<std::size_t>(k), -std::numeric_limits<double>::infinity());
  if (k == 0 || fresh.rows() == 0) return out;
  if (known.rows() > 0) {
    const topics::MotClassification own = topics::classify_mot(model, known);
    for (int c = 0; c < k; ++c) {
      std::vector<double> s;
      for (Eigen::Index i = 0; i < known.rows(); ++i) {
        if (known_labels[static_cast<std::size_t>(i)] == c) s.push_back(own.log_score(i, c));
      }
      if (s.empty()) continue;
      std::sort(s.begin(), s.end());
      const auto q =
          static_cast<std::size_t>(std::floor(kRepeatQuantile * static_cast<double>(s.size() - 1)));
      out.floors[static_cast<std::size_t>(c)] = s[q];
    }
  }
  const topics::MotClassification now = topics::classify_mot(model, fresh);
  for (Eigen::Index i = 0; i < fresh.rows(); ++i) {
    const int c = now.predicted[static_cast<std::size_t>(i)];
    const double floor = out.floors[static_cast<std::size_t>(c)];
    if (std::isfinite(floor) && now.log_score(i, c) >= floor) {
      out.shares[static_cast<std::size_t>(c)] += 1.0 / static_cast<double>(fresh.rows());
    }
  }
  double best = 0;
  for (int c = 0; c < k; ++c) {
    if (out.shares[static_cast<std::size_t>(c)] > best) {
      best = out.shares[static_cast<std::size_t>(c)];
      out.cls = c;
    }
  }
  if (best + 1e-12 < share) out.cls = -1;
  return out;
}

bool recheck_claimed(const NextChoice& claims, int chosen) {
  if (chosen < 0 || static_cast<std::size_t>(chosen) >= claims.claimed_by.size()) {
    throw Error("recheck_claimed: the chosen blob is not a blob of the claims");
  }
  if (claims.claimed_by[static_cast<std::size_t>(chosen)] < 0) return false;
  // choose_unlearned chose an unclaimed blob exactly when one was scored and left unclaimed.
  return claims.blob >= 0 && claims.claimed_by[static_cast<std::size_t>(claims.blob)] < 0;
}

namespace {

// What the choose_unlearned variants hand claim_blobs: `distance[b][c]`, a blob's distance to a
// class (inf: unscored or no part), the `scored` blobs and the `classes` taking part.
struct ClaimTable {
  std::vector<std::vector<double>> distance;
  std::vector<int> scored;
  std::vector<int> classes;
};

// The table of n blobs and k classes, every distance inf: the blobs b with has_blob(b) scored,
// the classes c with has_class(c) taking part (in order).
template <class HasBlob, class HasClass>
ClaimTable claim_table(int n, int k, const HasBlob& has_blob, const HasClass& has_class) {
  ClaimTable t;
  t.distance.assign(
      static_cast<std::size_t>(n),
      std::vector<double>(static_cast<std::size_t>(k), std::numeric_limits<double>::infinity()));
  for (int b = 0; b < n; ++b) {
    if (has_blob(b)) t.scored.push_back(b);
  }
  for (int c = 0; c < k; ++c) {
    if (has_class(c)) t.classes.push_back(c);
  }
  return t;
}

// choose_unlearned's nearest classes, matching and choice on `table`. Distances may be negative
// (choose_unlearned_by_words): the search prunes only when none is.
// `limit` (choose_unlearned_by_descriptors): a pair farther than it is no claim; the matching
// counts it at `limit`, the cost of a class that claims nothing.
NextChoice claim_blobs(const ClaimTable& table,
                       double limit = std::numeric_limits<double>::infinity()) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const std::vector<std::vector<double>>& distance = table.distance;
  const std::vector<int>& scored = table.scored;
  const std::vector<int>& classes = table.classes;
  const auto cost_of = [&](int b, int c) {
    return std::min(distance[static_cast<std::size_t>(b)][static_cast<std::size_t>(c)], limit);
  };
  const int n = static_cast<int>(distance.size());
  NextChoice out;
  out.claimed_by.assign(static_cast<std::size_t>(n), -1);
  out.nearest.assign(static_cast<std::size_t>(n), -1.0);
  out.nearest_class.assign(static_cast<std::size_t>(n), -1);
  for (const int b : scored) {
    double nearest = kInf;
    for (const int c : classes) {
      const double d = distance[static_cast<std::size_t>(b)][static_cast<std::size_t>(c)];
      if (d < nearest) {
        nearest = d;
        out.nearest_class[static_cast<std::size_t>(b)] = c;
      }
    }
    // No class has a part yet: every blob is as new as any other (distance 1, the most).
    out.nearest[static_cast<std::size_t>(b)] = std::isfinite(nearest) ? nearest : 1.0;
  }
  if (scored.empty()) return out;
  bool nonnegative = true;
  for (const int b : scored) {
    for (const int c : classes) {
      if (distance[static_cast<std::size_t>(b)][static_cast<std::size_t>(c)] < 0) {
        nonnegative = false;
      }
    }
  }
  // The matching of classes to scored blobs of least total distance, as many pairs as the
  // smaller side has: brute force (small tables), else greedy by least distance.
  const int pairs = std::min(static_cast<int>(classes.size()), static_cast<int>(scored.size()));
  std::vector<int> best(classes.size(), -1);
  if (pairs > 0 && classes.size() <= 8 && scored.size() <= 8) {
    double best_cost = kInf;
    std::vector<int> now(classes.size(), -1);
    std::vector<bool> used(static_cast<std::size_t>(n), false);
    const auto search = [&](const auto& self, std::size_t i, int made, double cost) -> void {
      if (nonnegative && cost >= best_cost) return;
      if (i == classes.size()) {
        if (made == pairs && cost < best_cost) {
          best_cost = cost;
          best = now;
        }
        return;
      }
      const int left = static_cast<int>(classes.size() - i);
      for (const int b : scored) {
        if (used[static_cast<std::size_t>(b)]) continue;
        used[static_cast<std::size_t>(b)] = true;
        now[i] = b;
        self(self, i + 1, made + 1, cost + cost_of(b, classes[i]));
        used[static_cast<std::size_t>(b)] = false;
        now[i] = -1;
      }
      if (pairs - made < left) self(self, i + 1, made, cost);  // this class claims none
    };
    search(search, 0, 0, 0.0);
  } else if (pairs > 0) {
    std::vector<bool> used(static_cast<std::size_t>(n), false);
    for (int made = 0; made < pairs; ++made) {
      double least = kInf;
      int bc = -1;
      int bb = -1;
      for (std::size_t i = 0; i < classes.size(); ++i) {
        if (best[i] >= 0) continue;
        for (const int b : scored) {
          const double d = cost_of(b, classes[i]);
          if (!used[static_cast<std::size_t>(b)] && (bc < 0 || d < least)) {
            least = d;
            bc = static_cast<int>(i);
            bb = b;
          }
        }
      }
      best[static_cast<std::size_t>(bc)] = bb;
      used[static_cast<std::size_t>(bb)] = true;
    }
  }
  for (std::size_t i = 0; i < classes.size(); ++i) {
    if (best[i] < 0) continue;
    const auto b = static_cast<std::size_t>(best[i]);
    if (distance[b][static_cast<std::size_t>(classes[i])] > limit) continue;  // no claim
    out.claimed_by[b] = classes[i];
  }
  // The unclaimed blob farthest from every class; every blob claimed: the farthest of all.
  for (const bool unclaimed_only : {true, false}) {
    double far = -kInf;
    for (const int b : scored) {
      if (unclaimed_only && out.claimed_by[static_cast<std::size_t>(b)] >= 0) continue;
      if (out.nearest[static_cast<std::size_t>(b)] > far) {
        far = out.nearest[static_cast<std::size_t>(b)];
        out.blob = b;
      }
    }
    if (out.blob >= 0) break;
  }
  return out;
}

}  // namespace

NextChoice choose_unlearned(const std::vector<Eigen::VectorXd>& blobs,
                            const std::vector<std::vector<Eigen::VectorXd>>& class_looks) {
  // distance[b][c]: the blob's least distance to class c's looks (inf: no looks or unscored).
  ClaimTable table = claim_table(
      static_cast<int>(blobs.size()), static_cast<int>(class_looks.size()),
      [&](int b) { return blobs[static_cast<std::size_t>(b)].size() > 0; },
      [&](int c) { return !class_looks[static_cast<std::size_t>(c)].empty(); });
  for (const int b : table.scored) {
    for (const int c : table.classes) {
      double& d = table.distance[static_cast<std::size_t>(b)][static_cast<std::size_t>(c)];
      for (const Eigen::VectorXd& e : class_looks[static_cast<std::size_t>(c)]) {
        d = std::min(d, hellinger(blobs[static_cast<std::size_t>(b)], e));
      }
    }
  }
  return claim_blobs(table);
}

NextChoice choose_unlearned_by_words(const std::vector<std::vector<std::int32_t>>& blobs,
                                     const std::vector<Eigen::VectorXd>& class_counts, int words) {
  if (words < 1) throw Error("choose_unlearned_by_words: the vocabulary has no words");
  const double v = words;
  for (const Eigen::VectorXd& counts : class_counts) {
    if (counts.size() != words) {
      throw Error(
          "choose_unlearned_by_words: a class's word counts are not the vocabulary's length");
    }
  }
  ClaimTable table = claim_table(
      static_cast<int>(blobs.size()), static_cast<int>(class_counts.size()),
      [&](int b) { return !blobs[static_cast<std::size_t>(b)].empty(); },
      [&](int c) { return class_counts[static_cast<std::size_t>(c)].sum() > 0; });
  // The background: the scored blobs' words pooled, add-one.
  Eigen::VectorXd p0 = Eigen::VectorXd::Ones(words);
  for (const int b : table.scored) {
    for (const std::int32_t w : blobs[static_cast<std::size_t>(b)]) {
      if (w < 0 || w >= words)
        throw Error("choose_unlearned_by_words: a word out of the vocabulary");
      p0[w] += 1.0;
    }
  }
  p0 /= p0.sum();
  for (const int c : table.classes) {
    const Eigen::VectorXd& counts = class_counts[static_cast<std::size_t>(c)];
    const Eigen::VectorXd pc = (counts + v * p0) / (counts.sum() + v);
    const Eigen::VectorXd llr = (pc.array() / p0.array()).log().matrix();
    for (const int b : table.scored) {
      const auto& d = blobs[static_cast<std::size_t>(b)];
      double sum = 0;
      for (const std::int32_t w : d) sum += llr[w];
      table.distance[static_cast<std::size_t>(b)][static_cast<std::size_t>(c)] =
          -sum / static_cast<double>(d.size());
    }
  }
  return claim_blobs(table);
}

NextChoice choose_unlearned_by_descriptors(const std::vector<cv::Mat>& blobs,
                                           const std::vector<cv::Mat>& class_descriptors,
                                           double ratio, double min_share) {
  if (!(ratio > 0 && ratio <= 1)) {
    throw Error("choose_unlearned_by_descriptors: the ratio must be in (0, 1]");
  }
  if (!(min_share >= 0 && min_share <= 1)) {
    throw Error("choose_unlearned_by_descriptors: min_share must be in [0, 1]");
  }
  for (const auto* set : {&blobs, &class_descriptors}) {
    for (const cv::Mat& d : *set) {
      if (!d.empty()) features::check_descriptors(d, "choose_unlearned_by_descriptors");
    }
  }
  constexpr double kInf = std::numeric_limits<double>::infinity();
  ClaimTable table = claim_table(
      static_cast<int>(blobs.size()), static_cast<int>(class_descriptors.size()),
      [&](int b) { return !blobs[static_cast<std::size_t>(b)].empty(); },
      [&](int c) { return !class_descriptors[static_cast<std::size_t>(c)].empty(); });
  const std::vector<int>& classes = table.classes;
  const std::vector<int>& scored = table.scored;
  // The objects a descriptor is matched against: the classes, then the look's scored blobs.
  std::vector<const cv::Mat*> objects;
  objects.reserve(classes.size() + scored.size());
  for (const int c : classes) objects.push_back(&class_descriptors[static_cast<std::size_t>(c)]);
  for (const int b : scored) objects.push_back(&blobs[static_cast<std::size_t>(b)]);
  cv::BFMatcher matcher(cv::NORM_L2);
  for (std::size_t bi = 0; bi < scored.size(); ++bi) {
    const cv::Mat& q = blobs[static_cast<std::size_t>(scored[bi])];
    // nearest(i, o): descriptor i's nearest distance in object o (inf: the blob itself).
    Eigen::MatrixXd nearest =
        Eigen::MatrixXd::Constant(q.rows, static_cast<Eigen::Index>(objects.size()), kInf);
    for (std::size_t o = 0; o < objects.size(); ++o) {
      if (o == classes.size() + bi) continue;  // not against itself
      std::vector<std::vector<cv::DMatch>> knn;
      matcher.knnMatch(q, *objects[o], knn, 1);
      for (const auto& m : knn) {
        if (!m.empty()) nearest(m[0].queryIdx, static_cast<Eigen::Index>(o)) = m[0].distance;
      }
    }
    std::vector<int> good(classes.size(), 0);
    for (Eigen::Index i = 0; i < nearest.rows(); ++i) {
      Eigen::Index first = 0;
      const double d1 = nearest.row(i).minCoeff(&first);
      if (static_cast<std::size_t>(first) >= classes.size() || !std::isfinite(d1)) continue;
      double d2 = kInf;  // the nearest of every other object
      for (Eigen::Index o = 0; o < nearest.cols(); ++o) {
        if (o != first) d2 = std::min(d2, nearest(i, o));
      }
      if (d1 < ratio * d2) ++good[static_cast<std::size_t>(first)];
    }
    for (std::size_t ci = 0; ci < classes.size(); ++ci) {
      table.distance[static_cast<std::size_t>(scored[bi])][static_cast<std::size_t>(classes[ci])] =
          -static_cast<double>(good[ci]) / static_cast<double>(q.rows);
    }
  }
  // No claim below min_share, nor without a single match (min_share 0).
  return claim_blobs(table, min_share > 0 ? -min_share : -1e-12);
}

Learning learn_by_pushing(robot::Robot& robot, TableAttendant& attendant, int classes,
                          const topics::LdaModel& model, const features::Vocabulary& vocabulary,
                          const SelfSupervisionOptions& options, const fs::path& episodes,
                          const fs::path& log_path, bool progress) {
  options.validate();
  if (classes < 1) throw Error("self-supervision: at least one object is needed");
  if (options.rounds > 0 && options.rounds < classes) {
    throw Error(core::cat({"self-supervision: --rounds ", std::to_string(options.rounds),
                           " is fewer than the ", std::to_string(classes),
                           " objects (0: one round an object)"}));
  }
  const int words = features::document_vocabulary_size(vocabulary, options.document_colour());
  if (words != model.num_words()) {
    throw Error(core::cat({"the vocabulary has ", std::to_string(vocabulary.size()), " words",
                           options.colour_words
                               ? " (+ " + std::to_string(options.colour.count()) + " colour words)"
                               : std::string(),
                           ", the LDA model ", std::to_string(model.num_words()),
                           ": not the vocabulary the model was made with"}));
  }
  if (options.views != ViewSource::kBlob && episodes.empty()) {
    throw Error("self-supervision: motion views need an episode directory");
  }
  if (!episodes.empty()) fs::create_directories(episodes);
  Learner learner(robot, attendant, classes, model, vocabulary, options, episodes, log_path);
  return learner.run(progress);
}

}  // namespace proprio::loop

#include "proprio/recognition/episode_classification.hpp"

#include <algorithm>
#include <cassert>
#include <chrono>
#include <map>
#include <opencv2/imgproc.hpp>

#include "proprio/core/error.hpp"
#include "proprio/episode/objects.hpp"

namespace proprio::recognition {
namespace {

// Episode object id -> class name, for the objects that are not the arm.
std::map<int, std::string> class_names(const episode::Episode& e,
                                       const std::vector<std::string>& objects) {
  std::map<int, std::string> out;
  for (const episode::ObjectInfo& o : e.objects())
    if (o.role != episode::ObjectRole::kArm) out[o.id] = object_class_name(o.name, objects);
  return out;
}

// The class holding most of `f`'s features in the id image, or "" when none lies on an object.
std::string majority_class(const features::Features& f, const cv::Mat& ids,
                           const std::map<int, std::string>& names) {
  std::map<std::string, int> votes;
  for (const cv::KeyPoint& k : f.keypoints) {
    const int x = std::clamp(cvRound(k.pt.x), 0, ids.cols - 1);
    const int y = std::clamp(cvRound(k.pt.y), 0, ids.rows - 1);
    const auto it = names.find(ids.at<std::uint16_t>(y, x));
    if (it != names.end()) ++votes[it->second];
  }
  std::string best;
  int most = 0;
  for (const auto& [name, n] : votes) {
    if (n > most) {
      best = name;
      most = n;
    }
  }
  return best;
}

void check_vocabulary(const topics::LdaModel& model, const features::Vocabulary& vocabulary) {
  if (model.num_words() != vocabulary.size()) {
    std::string m = "the model has ";
    m += std::to_string(model.num_words());
    m += " words but the vocabulary ";
    m += std::to_string(vocabulary.size());
    throw Error(m);
  }
  if (vocabulary.dimension() != features::kDescriptorLength) {
    throw Error("the vocabulary's words are not 128-D SIFT descriptors");
  }
}

}  // namespace

void EpisodeClassifyOptions::validate() const {
  frames.validate();
  if (frame_step < 1) throw Error("the frame step must be >= 1");
  inference.validate();
}

std::string object_class_name(const std::string& object_name,
                              const std::vector<std::string>& objects) {
  for (const std::string& n : objects) {
    const std::string suffix = "-" + n;
    if (object_name == n || (object_name.size() > suffix.size() && object_name.ends_with(suffix)))
      return n;
  }
  for (const char* prefix : {"scatter-", "distractor-", "neighbour-"}) {
    if (object_name.starts_with(prefix)) return object_name.substr(std::string(prefix).size());
  }
  return object_name;
}

EpisodeClassification classify_episodes(const std::vector<episode::Episode>& episodes,
                                        const topics::LdaModel& model,
                                        const features::Vocabulary& vocabulary,
                                        const EpisodeClassifyOptions& options,
                                        const ProgressFn& progress) {
  options.validate();
  check_vocabulary(model, vocabulary);
  if (episodes.empty()) throw Error("no episodes to classify");
  for (const auto& e : episodes)
    if (e.frame_count() < 1) throw Error::in_file(e.dir(), "the episode has no frames");
  const auto t0 = std::chrono::steady_clock::now();

  EpisodeClassification result;
  topics::Corpus corpus(vocabulary.size());
  std::vector<std::string> truth_names;
  std::size_t total = 0, done = 0;
  for (const auto& e : episodes)
    total +=
        static_cast<std::size_t>((e.frame_count() + options.frame_step - 1) / options.frame_step);
  for (std::size_t ei = 0; ei < episodes.size(); ++ei) {
    const episode::Episode& e = episodes[ei];
    const bool truth = e.info().has_masks;
    const std::map<int, std::string> names =
        truth ? class_names(e, options.frames.objects) : std::map<int, std::string>{};
    for (int i = 0; i < e.frame_count(); i += options.frame_step) {
      const std::vector<features::Features> docs = frame_features(e, i, options.frames);
      const cv::Mat ids = truth ? e.mask(i) : cv::Mat();
      for (std::size_t d = 0; d < docs.size(); ++d) {
        ClassifiedDocument c;
        c.episode = static_cast<int>(ei);
        c.frame = i;
        c.document = static_cast<int>(d);
        const auto tokens = docs[d].empty()
                                ? std::vector<std::int32_t>{}
                                : features::bag_of_words(vocabulary, docs[d].descriptors);
        c.tokens = static_cast<std::int64_t>(tokens.size());
        corpus.add_tokens(tokens);
        truth_names.push_back(truth ? majority_class(docs[d], ids, names) : std::string());
        result.documents.push_back(c);
      }
      ++result.summary.frames;
      if (progress) progress(++done, total);
    }
  }
  for (const std::string& n : truth_names)
    if (!n.empty() &&
        std::find(result.classes.begin(), result.classes.end(), n) == result.classes.end())
      result.classes.push_back(n);
  std::sort(result.classes.begin(), result.classes.end());

  const topics::InferenceResult r = topics::infer_topics(model, corpus, options.inference);
  result.theta = r.theta();
  const std::vector<int> topic = r.classify();
  std::vector<int> truth_rows, topic_rows;
  for (std::size_t d = 0; d < result.documents.size(); ++d) {
    ClassifiedDocument& c = result.documents[d];
    c.topic = topic[d];
    if (!truth_names[d].empty()) {
      c.truth =
          static_cast<int>(std::find(result.classes.begin(), result.classes.end(), truth_names[d]) -
                           result.classes.begin());
      truth_rows.push_back(c.truth);
      topic_rows.push_back(c.topic);
    }
  }
  if (!result.classes.empty()) {
    result.by_topic =
        confusion_matrix(truth_rows, topic_rows, result.classes, topic_names(model.num_topics()));
  }
  result.summary.episodes = static_cast<int>(episodes.size());
  result.summary.documents = static_cast<int>(result.documents.size());
  result.summary.empty_documents = r.summary.empty_documents;
  result.summary.tokens = corpus.num_tokens();
  result.summary.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  result.summary.message = "classified " + std::to_string(result.summary.documents) +
                           " documents of " + std::to_string(result.summary.frames) + " frames";
  return result;
}

ConfusionMatrix apply_mapping(EpisodeClassification& result, const TopicMapping& mapping,
                              const std::vector<std::string>& mapping_classes) {
  assert(static_cast<Eigen::Index>(mapping.topic_class.size()) == result.theta.cols());
  const std::vector<int> topics = [&] {
    std::vector<int> t;
    for (const auto& c : result.documents) t.push_back(c.topic);
    return t;
  }();
  const std::vector<int> mapped = mapped_classes(topics, mapping);
  std::vector<int> truth_rows, mapped_rows;
  for (std::size_t d = 0; d < result.documents.size(); ++d) {
    ClassifiedDocument& c = result.documents[d];
    c.mapped = mapped[d];
    if (c.truth < 0) continue;
    const std::string& name = result.classes[static_cast<std::size_t>(c.truth)];
    const auto it = std::find(mapping_classes.begin(), mapping_classes.end(), name);
    if (it == mapping_classes.end()) continue;
    truth_rows.push_back(static_cast<int>(it - mapping_classes.begin()));
    mapped_rows.push_back(c.mapped);
  }
  return confusion_matrix(truth_rows, mapped_rows, mapping_classes, mapping_classes);
}

LabelledFeatures object_view_features(const std::vector<episode::Episode>& episodes,
                                      const std::vector<std::vector<int>>& frames,
                                      const std::vector<std::string>& classes,
                                      const features::ExtractOptions& options, int min_features,
                                      int dilate, int erode, ViewSelection selection,
                                      int erode_min_features) {
  assert(frames.size() == episodes.size());
  options.validate();
  if (min_features < 1) throw Error("a view needs at least 1 feature");
  if (dilate < 0) throw Error("the mask growth must be >= 0 pixels");
  check_mask_change(dilate, erode);
  check_erode_min_features(erode_min_features);
  LabelledFeatures out{{}, {}, classes, {}};
  for (std::size_t ei = 0; ei < episodes.size(); ++ei) {
    const episode::Episode& e = episodes[ei];
    if (!e.info().has_masks) throw Error::in_file(e.dir(), "the episode has no ground-truth masks");
    std::vector<std::pair<int, int>> wanted;  // object id, class
    for (const auto& [id, name] : class_names(e, classes)) {
      const auto it = std::find(classes.begin(), classes.end(), name);
      if (it != classes.end()) wanted.emplace_back(id, static_cast<int>(it - classes.begin()));
    }
    for (int i : frames[ei]) {
      const cv::Mat ids = e.mask(i);
      const cv::Mat image = e.frame(i);
      for (const auto& [id, label] : wanted) {
        const cv::Mat m = object_mask(ids, id, dilate, erode);
        const cv::Mat bare = dilate > 0 || erode > 0 ? object_mask(ids, id, 0, 0) : m;
        auto origin = [&] {
          const int rows = bare.rows - 1;
          const int cols = bare.cols - 1;
          const bool border =
              cv::countNonZero(bare.row(0)) > 0 || cv::countNonZero(bare.row(rows)) > 0 ||
              cv::countNonZero(bare.col(0)) > 0 || cv::countNonZero(bare.col(cols)) > 0;
          return ViewOrigin{static_cast<int>(ei), i, cv::countNonZero(bare), border};
        };
        const bool adaptive = erode > 0 && erode_min_features > 0;
        if (adaptive || (selection == ViewSelection::kBareMask && (dilate > 0 || erode > 0))) {
          // Chosen by the bare mask's (kBareMask) or the cut's features, cut by m or, adaptive,
          // by the bare mask shrunk by adaptive_erosion: extracted once over both masks (the
          // grid points and descriptors do not depend on the mask, only which points are kept).
          if (cv::countNonZero(bare) == 0) continue;
          cv::Mat both;
          cv::bitwise_or(bare, m, both);
          const features::Features all = features::extract_features(image, options, both);
          const cv::Mat cut =
              adaptive
                  ? object_mask(ids, id, 0,
                                adaptive_erosion(ids, id, erode, erode_min_features, all.keypoints))
                  : m;
          int on_bare = 0;
          std::vector<int> rows;
          for (int r = 0; r < all.size(); ++r) {
            const cv::KeyPoint& k = all.keypoints[static_cast<std::size_t>(r)];
            if (on_mask(bare, k)) ++on_bare;
            if (on_mask(cut, k)) rows.push_back(r);
          }
          const int kept =
              selection == ViewSelection::kBareMask ? on_bare : static_cast<int>(rows.size());
          if (kept < min_features) continue;
          out.views.push_back(features::select_features(all, rows));
          out.labels.push_back(label);
          out.origins.push_back(origin());
          continue;
        }
        if (cv::countNonZero(m) == 0) continue;
        features::Features f = features::extract_features(image, options, m);
        if (f.size() < min_features) continue;
        out.views.push_back(std::move(f));
        out.labels.push_back(label);
        out.origins.push_back(origin());
      }
    }
  }
  return out;
}

LabelledCorpus views_corpus(const LabelledFeatures& views, const features::Vocabulary& vocabulary) {
  LabelledCorpus out{topics::Corpus(vocabulary.size()), views.labels, views.classes};
  for (const features::Features& f : views.views)
    out.corpus.add_tokens(features::bag_of_words(vocabulary, f.descriptors));
  return out;
}

LabelledCorpus object_view_corpus(const std::vector<episode::Episode>& episodes,
                                  const std::vector<std::vector<int>>& frames,
                                  const std::vector<std::string>& classes,
                                  const features::Vocabulary& vocabulary,
                                  const features::ExtractOptions& options, int min_features,
                                  int dilate, int erode, ViewSelection selection,
                                  int erode_min_features) {
  return views_corpus(object_view_features(episodes, frames, classes, options, min_features, dilate,
                                           erode, selection, erode_min_features),
                      vocabulary);
}

}  // namespace proprio::recognition

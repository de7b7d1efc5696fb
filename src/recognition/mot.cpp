#include "proprio/recognition/mot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <set>
#include <sstream>

#include "proprio/core/binary_file.hpp"
#include "proprio/core/error.hpp"
#include "proprio/core/files.hpp"
#include "proprio/core/text.hpp"
#include "proprio/episode/discovery.hpp"
#include "proprio/episode/episode.hpp"
#include "proprio/features/image_set.hpp"
#include "proprio/recognition/episode_classification.hpp"
#include "proprio/topics/lda_model_io.hpp"

namespace proprio::recognition {
namespace fs = std::filesystem;

namespace {

/// The documents of `t` that have words (theta is undefined for the others) and their theta rows.
struct NonEmpty {
  std::vector<int> rows;  ///< document indices
  Eigen::MatrixXd theta;  ///< one row per entry of `rows`
};

NonEmpty non_empty(const DocumentTheta& t) {
  NonEmpty n;
  for (std::size_t d = 0; d < t.empty.size(); ++d)
    if (!t.empty[d]) n.rows.push_back(static_cast<int>(d));
  n.theta.resize(static_cast<Eigen::Index>(n.rows.size()), t.theta.cols());
  for (std::size_t i = 0; i < n.rows.size(); ++i)
    n.theta.row(static_cast<Eigen::Index>(i)) = t.theta.row(n.rows[i]);
  return n;
}

/// Every document's predicted class (-1 for the empty ones), from the classes of `n`'s rows
/// mapped through `name` (the identity when empty).
std::vector<int> predictions(const NonEmpty& n, std::size_t documents,
                             const std::vector<int>& classified,
                             const std::vector<int>& name = {}) {
  std::vector<int> predicted(documents, -1);
  for (std::size_t i = 0; i < n.rows.size(); ++i) {
    const int c = classified[i];
    predicted[static_cast<std::size_t>(n.rows[i])] =
        name.empty() ? c : name[static_cast<std::size_t>(c)];
  }
  return predicted;
}

std::string hex(std::uint32_t v) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "%08x", v);
  return buf;
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string q = "\"";
  for (const char c : s) {
    if (c == '"') q += '"';
    q += c;
  }
  return q + '"';
}

std::vector<std::string> split_names(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream s(text);
  std::string item;
  while (std::getline(s, item, ',')) {
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

/// The views of a source: labelled documents and where each came from.
struct Views {
  LabelledCorpus docs;
  std::vector<std::string> where;  ///< image file or episode directory
  std::vector<int> frame;          ///< -1 for images
};

void append(LabelledCorpus& to, const LabelledCorpus& from, std::vector<std::string>& where,
            std::vector<int>& frame, const std::string& w, int f) {
  for (std::size_t d = 0; d < from.corpus.num_documents(); ++d) {
    const topics::DocumentView doc = from.corpus.document(d);
    to.corpus.add_document(doc.words, doc.counts);
    to.labels.push_back(from.labels[d]);
    where.push_back(w);
    frame.push_back(f);
  }
}

Views read_views(const MotSourceOptions& o, const features::Vocabulary& vocabulary) {
  Views v;
  if (!o.images.empty()) {
    const features::ImageSet set = features::read_image_set(o.images);
    std::vector<std::size_t> all(set.images.size());
    std::iota(all.begin(), all.end(), std::size_t{0});
    v.docs = image_corpus(set, all, vocabulary, o.features);
    for (const auto& p : set.images) v.where.push_back(p.string());
    v.frame.assign(set.images.size(), -1);
    return v;
  }
  std::vector<episode::Episode> episodes;
  for (const fs::path& d : episode::find_episodes({o.episodes}))
    episodes.push_back(episode::read_episode(d));
  if (episodes.empty()) throw Error::in_file(o.episodes, "no episodes there");
  std::vector<std::string> classes = split_names(o.objects);
  if (classes.empty()) {
    std::set<std::string> names;
    for (const auto& e : episodes) {
      for (const auto& obj : e.objects())
        if (obj.role != episode::ObjectRole::kArm) names.insert(object_class_name(obj.name));
    }
    classes.assign(names.begin(), names.end());
  }
  if (classes.empty()) throw Error::in_file(o.episodes, "the episodes have no objects");
  v.docs = LabelledCorpus{topics::Corpus(vocabulary.size()), {}, classes};
  for (const auto& e : episodes) {
    const std::vector<episode::Episode> one{e};
    for (int i = 0; i < e.frame_count(); i += o.view_step) {
      const LabelledCorpus c =
          object_view_corpus(one, {{i}}, classes, vocabulary, o.features, o.min_features, o.dilate);
      append(v.docs, c, v.where, v.frame, e.dir().string(), i);
    }
  }
  return v;
}

void check_words(const topics::LdaModel& model, const features::Vocabulary& vocabulary,
                 const fs::path& where) {
  if (model.num_words() != vocabulary.size()) {
    throw Error::in_file(where, "the LDA model has " + std::to_string(model.num_words()) +
                                    " words but the vocabulary " +
                                    std::to_string(vocabulary.size()) +
                                    ": they do not belong together");
  }
}

// The views of `source` with their theta, read after checking that its LDA model and vocabulary
// belong together (and, with `mot`, that they are the ones the MoT model was built on).
struct SourceTheta {
  topics::LdaModel lda;
  std::uint32_t vocabulary_checksum = 0;
  Views views;
  DocumentTheta dt;
};

SourceTheta read_source_theta(const MotSourceOptions& source,
                              const topics::MotModelFile* mot = nullptr,
                              const fs::path& mot_file = {}) {
  SourceTheta out;
  out.lda = topics::load_lda_model(source.lda_model);
  const features::Vocabulary vocabulary = features::read_vocabulary(source.vocabulary);
  check_words(out.lda, vocabulary, source.lda_model);
  out.vocabulary_checksum = vocabulary_checksum(vocabulary);
  if (mot != nullptr)
    topics::check_mot_basis(mot->basis, out.lda, &out.vocabulary_checksum, mot_file);
  out.views = read_views(source, vocabulary);
  out.dt = document_theta(out.lda, out.views.docs.corpus);
  return out;
}

}  // namespace

DocumentTheta document_theta(const topics::LdaModel& model, const topics::Corpus& corpus,
                             const topics::InferenceOptions& options) {
  const topics::InferenceResult r = topics::infer_topics(model, corpus, options);
  DocumentTheta out{r.theta(), {}};
  for (const auto t : r.tokens) out.empty.push_back(t == 0);
  return out;
}

DocumentTheta word_posterior_theta(const topics::LdaModel& model, const topics::Corpus& corpus) {
  if (static_cast<int>(corpus.num_words()) != model.num_words()) {
    throw Error("the corpus has " + std::to_string(corpus.num_words()) + " words, the LDA model " +
                std::to_string(model.num_words()));
  }
  const Eigen::MatrixXd beta = model.topic_word();
  // p(k | w) per word: the columns of beta normalised.
  Eigen::MatrixXd post = beta;
  for (Eigen::Index w = 0; w < post.cols(); ++w) post.col(w) /= post.col(w).sum();
  const auto k = static_cast<Eigen::Index>(model.num_topics());
  const auto n = static_cast<Eigen::Index>(corpus.num_documents());
  DocumentTheta out{Eigen::MatrixXd::Constant(n, k, 1.0 / static_cast<double>(k)), {}};
  for (Eigen::Index d = 0; d < n; ++d) {
    const topics::DocumentView doc = corpus.document(static_cast<std::size_t>(d));
    Eigen::VectorXd sum = Eigen::VectorXd::Zero(k);
    double tokens = 0;
    for (std::size_t i = 0; i < doc.size(); ++i) {
      sum += static_cast<double>(doc.counts[i]) * post.col(doc.words[i]);
      tokens += doc.counts[i];
    }
    out.empty.push_back(tokens == 0);
    if (tokens > 0) out.theta.row(d) = (sum / sum.sum()).transpose();
  }
  return out;
}

DocumentTheta view_theta(const topics::LdaModel& model, const topics::Corpus& corpus,
                         ThetaSource source, const topics::InferenceOptions& options) {
  return source == ThetaSource::kEStep ? document_theta(model, corpus, options)
                                       : word_posterior_theta(model, corpus);
}

MotEvaluation evaluate_mot(const topics::LdaModel& model, const LabelledCorpus& train,
                           const LabelledCorpus& test, const topics::MotOptions& options,
                           const topics::InferenceOptions& inference) {
  return evaluate_mot(model, train, test, options, inference, ThetaSource::kEStep);
}

MotEvaluation evaluate_mot(const topics::LdaModel& model, const LabelledCorpus& train,
                           const LabelledCorpus& test, const topics::MotOptions& options,
                           const topics::InferenceOptions& inference, ThetaSource source) {
  require(train.classes == test.classes, "evaluate_mot: training and test classes differ");
  const DocumentTheta known = view_theta(model, train.corpus, source, inference);
  std::vector<int> labels = train.labels;
  for (std::size_t d = 0; d < labels.size(); ++d)
    if (known.empty[d]) labels[d] = -1;
  MotEvaluation e;
  e.fit = topics::fit_mot(known.theta, labels, train.classes, options);
  const DocumentTheta t = view_theta(model, test.corpus, source, inference);
  const NonEmpty test_rows = non_empty(t);
  e.classified = test_rows.rows;
  e.classification = topics::classify_mot(e.fit.model, test_rows.theta, options.fit.proportions);
  const std::vector<int> predicted =
      predictions(test_rows, t.empty.size(), e.classification.predicted);
  e.classes = confusion_matrix(test.labels, predicted, test.classes, test.classes);
  return e;
}

MotUnsupervisedEvaluation evaluate_mot_unsupervised(const topics::LdaModel& model,
                                                    const LabelledCorpus& train,
                                                    const LabelledCorpus& test,
                                                    const topics::MotOptions& options,
                                                    const topics::InferenceOptions& inference) {
  require(train.classes == test.classes, "evaluate_mot_unsupervised: classes differ");
  const int n_classes = static_cast<int>(train.classes.size());
  const NonEmpty known = non_empty(document_theta(model, train.corpus, inference));
  const std::vector<int>& rows = known.rows;
  const Eigen::MatrixXd& theta = known.theta;
  MotUnsupervisedEvaluation e;
  topics::MotOptions o = options;
  o.classes = 0;
  e.chosen_classes = topics::fit_mot_unsupervised(theta, o).model.num_classes();
  for (int c = 0; c < n_classes; ++c) {
    std::vector<Eigen::Index> mine;
    for (std::size_t i = 0; i < rows.size(); ++i)
      if (train.labels[static_cast<std::size_t>(rows[i])] == c)
        mine.push_back(static_cast<Eigen::Index>(i));
    if (mine.size() < 4) {
      e.chosen_per_class.push_back(0);
      continue;
    }
    Eigen::MatrixXd one(static_cast<Eigen::Index>(mine.size()), theta.cols());
    for (std::size_t i = 0; i < mine.size(); ++i)
      one.row(static_cast<Eigen::Index>(i)) = theta.row(mine[i]);
    e.chosen_per_class.push_back(topics::fit_mot_unsupervised(one, o).model.num_classes());
  }
  o.classes = n_classes;
  e.fit = topics::fit_mot_unsupervised(theta, o);
  // Name each object after the majority class of its training documents.
  std::vector<std::vector<int>> votes(static_cast<std::size_t>(e.fit.model.num_classes()),
                                      std::vector<int>(static_cast<std::size_t>(n_classes), 0));
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const int label = train.labels[static_cast<std::size_t>(rows[i])];
    if (label >= 0)
      ++votes[static_cast<std::size_t>(e.fit.assignment[i])][static_cast<std::size_t>(label)];
  }
  for (const auto& v : votes)
    e.object_class.push_back(static_cast<int>(std::max_element(v.begin(), v.end()) - v.begin()));
  const DocumentTheta t = document_theta(model, test.corpus, inference);
  const NonEmpty test_rows = non_empty(t);
  const topics::MotClassification c =
      topics::classify_mot(e.fit.model, test_rows.theta, options.fit.proportions);
  const std::vector<int> predicted =
      predictions(test_rows, t.empty.size(), c.predicted, e.object_class);
  e.classes = confusion_matrix(test.labels, predicted, test.classes, test.classes);
  return e;
}

std::vector<int> knn_predict(const Eigen::MatrixXd& train, std::span<const int> labels, int classes,
                             const Eigen::MatrixXd& test, int k) {
  ensure(static_cast<std::size_t>(train.rows()) == labels.size() && train.cols() == test.cols() &&
             k >= 1 && classes >= 1,
         "knn_predict: bad shapes");
  std::vector<Eigen::Index> known;
  for (Eigen::Index i = 0; i < train.rows(); ++i)
    if (labels[static_cast<std::size_t>(i)] >= 0) known.push_back(i);
  std::vector<int> out(static_cast<std::size_t>(test.rows()), -1);
  if (known.empty()) return out;
  const auto kk = std::min(static_cast<std::size_t>(k), known.size());
  std::vector<std::pair<double, int>> d(known.size());
  for (Eigen::Index t = 0; t < test.rows(); ++t) {
    for (std::size_t i = 0; i < known.size(); ++i)
      d[i] = {(train.row(known[i]) - test.row(t)).squaredNorm(),
              labels[static_cast<std::size_t>(known[i])]};
    std::partial_sort(d.begin(), d.begin() + static_cast<long>(kk), d.end());
    std::vector<int> votes(static_cast<std::size_t>(classes), 0);
    for (std::size_t i = 0; i < kk; ++i) ++votes[static_cast<std::size_t>(d[i].second)];
    const int most = *std::max_element(votes.begin(), votes.end());
    // Ties: the class of the nearest neighbour among the tied classes.
    for (std::size_t i = 0; i < kk; ++i) {
      if (votes[static_cast<std::size_t>(d[i].second)] == most) {
        out[static_cast<std::size_t>(t)] = d[i].second;
        break;
      }
    }
  }
  return out;
}

std::vector<int> logistic_predict(const Eigen::MatrixXd& train, std::span<const int> labels,
                                  int classes, const Eigen::MatrixXd& test, double l2,
                                  int iterations) {
  ensure(static_cast<std::size_t>(train.rows()) == labels.size() && train.cols() == test.cols() &&
             classes >= 1 && iterations >= 1 && l2 >= 0,
         "logistic_predict: bad shapes or options");
  std::vector<Eigen::Index> known;
  for (Eigen::Index i = 0; i < train.rows(); ++i)
    if (labels[static_cast<std::size_t>(i)] >= 0) known.push_back(i);
  std::vector<int> out(static_cast<std::size_t>(test.rows()), -1);
  if (known.empty()) return out;
  const Eigen::Index n = static_cast<Eigen::Index>(known.size());
  const Eigen::Index f = train.cols();
  // Standardised features with a constant column for the bias.
  Eigen::MatrixXd x(n, f);
  for (Eigen::Index i = 0; i < n; ++i) x.row(i) = train.row(known[static_cast<std::size_t>(i)]);
  const Eigen::RowVectorXd mean = x.colwise().mean();
  Eigen::RowVectorXd sd =
      ((x.rowwise() - mean).array().square().colwise().sum() / static_cast<double>(n)).sqrt();
  for (Eigen::Index j = 0; j < f; ++j)
    if (!(sd(j) > 1e-12)) sd(j) = 1;
  auto design = [&](const Eigen::MatrixXd& m) {
    Eigen::MatrixXd z(m.rows(), f + 1);
    z.leftCols(f) = (m.rowwise() - mean).array().rowwise() / sd.array();
    z.col(f).setOnes();
    return z;
  };
  const Eigen::MatrixXd z = design(x);
  Eigen::MatrixXd y = Eigen::MatrixXd::Zero(n, classes);
  for (Eigen::Index i = 0; i < n; ++i) y(i, labels[static_cast<std::size_t>(known[i])]) = 1;
  Eigen::MatrixXd w = Eigen::MatrixXd::Zero(f + 1, classes);
  auto softmax = [](Eigen::MatrixXd s) {
    for (Eigen::Index i = 0; i < s.rows(); ++i) {
      s.row(i).array() -= s.row(i).maxCoeff();
      s.row(i) = s.row(i).array().exp().matrix();
      s.row(i) /= s.row(i).sum();
    }
    return s;
  };
  // The loss is convex with a gradient whose Lipschitz constant is at most the mean squared norm
  // of a standardised row (about f + 1) / 2: a step of 1 / (f + 1) is safe.
  const double step = 1.0 / static_cast<double>(f + 1);
  for (int it = 0; it < iterations; ++it) {
    const Eigen::MatrixXd p = softmax(z * w);
    Eigen::MatrixXd g = z.transpose() * (p - y) / static_cast<double>(n);
    g.topRows(f) += l2 * w.topRows(f);
    w -= step * g;
  }
  const Eigen::MatrixXd s = design(test) * w;
  for (Eigen::Index t = 0; t < s.rows(); ++t) {
    Eigen::Index best = 0;
    s.row(t).maxCoeff(&best);
    out[static_cast<std::size_t>(t)] = static_cast<int>(best);
  }
  return out;
}

std::vector<int> naive_bayes_predict(const LabelledCorpus& train, const topics::Corpus& test) {
  require(train.corpus.num_words() == test.num_words(), "naive_bayes_predict: vocabularies differ");
  const auto classes = static_cast<Eigen::Index>(train.classes.size());
  const Eigen::Index words = train.corpus.num_words();
  Eigen::MatrixXd counts = Eigen::MatrixXd::Ones(classes, words);
  for (std::size_t d = 0; d < train.corpus.num_documents(); ++d) {
    const int c = train.labels[d];
    if (c < 0) continue;
    const topics::DocumentView doc = train.corpus.document(d);
    for (std::size_t i = 0; i < doc.size(); ++i) counts(c, doc.words[i]) += doc.counts[i];
  }
  Eigen::MatrixXd log_p = counts;
  for (Eigen::Index c = 0; c < classes; ++c)
    log_p.row(c) = (counts.row(c) / counts.row(c).sum()).array().log().matrix();
  std::vector<int> out(test.num_documents(), -1);
  for (std::size_t d = 0; d < test.num_documents(); ++d) {
    const topics::DocumentView doc = test.document(d);
    if (doc.size() == 0) continue;
    Eigen::VectorXd score = Eigen::VectorXd::Zero(classes);
    for (std::size_t i = 0; i < doc.size(); ++i)
      score += static_cast<double>(doc.counts[i]) * log_p.col(doc.words[i]);
    Eigen::Index best = 0;
    score.maxCoeff(&best);
    out[d] = static_cast<int>(best);
  }
  return out;
}

namespace {

// Word proportions of each document, square-rooted (Euclidean distance between rows = the
// Hellinger distance up to a factor); empty documents are zero rows.
Eigen::MatrixXd sqrt_word_proportions(const topics::Corpus& corpus) {
  Eigen::MatrixXd out =
      Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(corpus.num_documents()), corpus.num_words());
  for (std::size_t d = 0; d < corpus.num_documents(); ++d) {
    const topics::DocumentView doc = corpus.document(d);
    double n = 0;
    for (std::size_t i = 0; i < doc.size(); ++i) n += doc.counts[i];
    for (std::size_t i = 0; i < doc.size(); ++i)
      out(static_cast<Eigen::Index>(d), doc.words[i]) = std::sqrt(doc.counts[i] / n);
  }
  return out;
}

}  // namespace

std::vector<RepresentationCeiling> representation_ceilings(
    const topics::LdaModel& model, const LabelledCorpus& train, const LabelledCorpus& test,
    const topics::InferenceOptions& inference) {
  require(train.classes == test.classes, "representation_ceilings: classes differ");
  const int classes = static_cast<int>(train.classes.size());
  std::vector<RepresentationCeiling> out;
  auto add = [&](const char* name, std::vector<int> predicted, const std::vector<bool>& empty) {
    for (std::size_t d = 0; d < predicted.size(); ++d)
      if (empty[d]) predicted[d] = -1;
    out.push_back({name, confusion_matrix(test.labels, predicted, test.classes, test.classes)});
  };
  for (const auto source : {ThetaSource::kEStep, ThetaSource::kWordPosterior}) {
    const DocumentTheta a = view_theta(model, train.corpus, source, inference);
    const DocumentTheta b = view_theta(model, test.corpus, source, inference);
    std::vector<int> labels = train.labels;
    for (std::size_t d = 0; d < labels.size(); ++d)
      if (a.empty[d]) labels[d] = -1;
    const bool estep = source == ThetaSource::kEStep;
    add(estep ? "knn-estep" : "knn-word-posterior",
        knn_predict(a.theta.array().sqrt().matrix(), labels, classes,
                    b.theta.array().sqrt().matrix(), 5),
        b.empty);
    const double s = 0.01;
    const double u = s / static_cast<double>(a.theta.cols());
    add(estep ? "logistic-estep" : "logistic-word-posterior",
        logistic_predict(((1 - s) * a.theta.array() + u).log().matrix(), labels, classes,
                         ((1 - s) * b.theta.array() + u).log().matrix()),
        b.empty);
  }
  std::vector<bool> empty(test.corpus.num_documents());
  for (std::size_t d = 0; d < empty.size(); ++d) empty[d] = test.corpus.document(d).size() == 0;
  add("knn-words",
      knn_predict(sqrt_word_proportions(train.corpus), train.labels, classes,
                  sqrt_word_proportions(test.corpus), 5),
      empty);
  add("naive-bayes-words", naive_bayes_predict(train, test.corpus), empty);
  return out;
}

std::uint32_t vocabulary_checksum(const features::Vocabulary& vocabulary) {
  std::string bytes;
  core::put_binary(bytes, static_cast<std::uint32_t>(vocabulary.size()));
  core::put_binary(bytes, static_cast<std::uint32_t>(vocabulary.dimension()));
  const cv::Mat w =
      vocabulary.words().isContinuous() ? vocabulary.words() : vocabulary.words().clone();
  bytes.append(reinterpret_cast<const char*>(w.data), w.total() * w.elemSize());
  return core::crc32(bytes);
}

void MotSourceOptions::validate() const {
  if (lda_model.empty() || vocabulary.empty()) {
    throw Error("mot: the LDA model and the vocabulary are required");
  }
  if (images.empty() == episodes.empty()) {
    throw Error("mot: give either the images (a folder per object) or the episodes");
  }
  core::check_field_bounds(*this, "mot");
  features.validate();
}

void MotTrainOptions::validate() const {
  source.validate();
  if (model.empty()) throw Error("mot train: the model file to write is required");
  mot.validate();
}

std::string MotTrainResult::brief() const {
  return fit.summary.brief() + " (" + std::to_string(empty_documents) +
         " views without features left out)";
}

MotTrainResult run_mot_train(const MotTrainOptions& options, const core::Provenance& provenance) {
  options.validate();
  const SourceTheta in = read_source_theta(options.source);
  const Views& views = in.views;
  const DocumentTheta& dt = in.dt;
  MotTrainResult r;
  r.documents = static_cast<int>(dt.empty.size());
  for (const bool e : dt.empty) r.empty_documents += e ? 1 : 0;
  if (options.unsupervised) {
    Eigen::MatrixXd theta(r.documents - r.empty_documents, dt.theta.cols());
    Eigen::Index row = 0;
    for (std::size_t d = 0; d < dt.empty.size(); ++d)
      if (!dt.empty[d]) theta.row(row++) = dt.theta.row(static_cast<Eigen::Index>(d));
    r.fit = topics::fit_mot_unsupervised(theta, options.mot);
  } else {
    std::vector<int> labels = views.docs.labels;
    for (std::size_t d = 0; d < labels.size(); ++d)
      if (dt.empty[d]) labels[d] = -1;
    r.fit = topics::fit_mot(dt.theta, labels, views.docs.classes, options.mot);
  }
  r.basis = topics::mot_basis(in.lda, &in.vocabulary_checksum);
  topics::save_mot_model(r.fit.model, r.basis, options.model);

  r.model_file = options.model;
  r.source = MotSourceRecord::of(options.source);
  r.unsupervised = options.unsupervised;
  r.options = options.mot;
  r.document = core::result_document("proprio.mot.train", 1, provenance);
  core::fields_into_json(r, r.document);
  r.message = core::first_line(r.brief());
  return r;
}

void MotClassifyOptions::validate() const {
  source.validate();
  if (model.empty() || out.empty()) {
    throw Error("mot classify: the model file and the output CSV are required");
  }
}

std::string MotClassifyResult::brief() const {
  char buf[200];
  std::snprintf(buf, sizeof buf,
                "%d views (%d without features): accuracy %.1f%%, mean class accuracy %.1f%%",
                documents, empty_documents, 100 * confusion.accuracy(),
                100 * confusion.mean_class_accuracy());
  return buf;
}

MotClassifyResult run_mot_classify(const MotClassifyOptions& options,
                                   const core::Provenance& provenance) {
  options.validate();
  const topics::MotModelFile file = topics::load_mot_model(options.model);
  const SourceTheta in = read_source_theta(options.source, &file, options.model);
  const Views& views = in.views;
  const DocumentTheta& dt = in.dt;

  MotClassifyResult r;
  r.documents = static_cast<int>(dt.empty.size());
  const NonEmpty known = non_empty(dt);
  const std::vector<int>& rows = known.rows;
  r.empty_documents = r.documents - static_cast<int>(rows.size());
  topics::MotClassification c;
  if (options.by == MotClassifyBy::kWords) {
    // The same views (those with features), scored by their words.
    topics::Corpus words(in.lda.num_words());
    for (const int d : rows) {
      const topics::DocumentView doc = views.docs.corpus.document(static_cast<std::size_t>(d));
      words.add_document(doc.words, doc.counts);
    }
    c = topics::classify_mot_words(file.model, in.lda, words);
  } else {
    c = topics::classify_mot(file.model, known.theta);
  }

  // Rows of the confusion matrix: the model's objects, then any true class it does not know, so
  // that the diagonal counts the views given their own object.
  const std::vector<std::string> names = file.model.names();
  std::vector<std::string> truth_names = names;
  std::vector<int> truth(dt.empty.size(), -1);
  for (std::size_t d = 0; d < truth.size(); ++d) {
    const int l = views.docs.labels[d];
    if (l < 0) continue;
    const std::string& n = views.docs.classes[static_cast<std::size_t>(l)];
    auto it = std::find(truth_names.begin(), truth_names.end(), n);
    if (it == truth_names.end()) it = truth_names.insert(truth_names.end(), n);
    truth[d] = static_cast<int>(it - truth_names.begin());
  }
  const std::vector<int> predicted = predictions(known, dt.empty.size(), c.predicted);
  // Documents without a truth (none today) cannot be counted in the matrix.
  std::vector<int> t_known, p_known;
  for (std::size_t d = 0; d < truth.size(); ++d) {
    if (truth[d] < 0) continue;
    t_known.push_back(truth[d]);
    p_known.push_back(predicted[d]);
  }
  r.confusion = confusion_matrix(t_known, p_known, truth_names, names);

  std::string csv = "document,source,frame,truth,class";
  for (const auto& n : names) {
    std::string column = "p_";
    column += n;
    csv += ',';
    csv += csv_field(column);
  }
  csv += '\n';
  std::size_t next = 0;
  for (std::size_t d = 0; d < dt.empty.size(); ++d) {
    csv += std::to_string(d) + ',' + csv_field(views.where[d]) + ',' +
           std::to_string(views.frame[d]) + ',';
    if (truth[d] >= 0) csv += csv_field(truth_names[static_cast<std::size_t>(truth[d])]);
    csv += ',';
    const bool classified = next < rows.size() && rows[next] == static_cast<int>(d);
    if (classified) csv += csv_field(names[static_cast<std::size_t>(c.predicted[next])]);
    for (std::size_t k = 0; k < names.size(); ++k) {
      csv += ',';
      if (classified) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%.6g",
                      c.posterior(static_cast<Eigen::Index>(next), static_cast<Eigen::Index>(k)));
        csv += buf;
      }
    }
    if (classified) ++next;
    csv += '\n';
  }
  core::write_file_atomic(options.out, csv);

  r.model_file = options.model;
  r.source = MotSourceRecord::of(options.source);
  r.out = options.out;
  r.by = options.by;
  r.document = core::result_document("proprio.mot.classify", 1, provenance);
  core::fields_into_json(r, r.document);
  r.message = core::first_line(r.brief());
  return r;
}

void MotUpdateOptions::validate() const {
  source.validate();
  if (model.empty()) throw Error("mot update: the model file to update is required");
  if (out.empty()) throw Error("mot update: the file to write the updated model to is required");
  mot.validate();
}

std::string MotUpdateResult::brief() const {
  std::ostringstream s;
  s << summary.views << " new views (" << empty_documents << " without features skipped), "
    << summary.fits.size() << " objects refitted, " << summary.new_objects << " new; "
    << model.num_classes() << " objects now";
  return s.str();
}

MotUpdateResult run_mot_update(const MotUpdateOptions& options,
                               const core::Provenance& provenance) {
  options.validate();
  topics::MotModelFile file = topics::load_mot_model(options.model);
  const SourceTheta in = read_source_theta(options.source, &file, options.model);
  const Views& views = in.views;
  const DocumentTheta& dt = in.dt;

  MotUpdateResult r;
  r.documents = static_cast<int>(dt.empty.size());
  std::vector<std::string> labels(dt.empty.size());
  for (std::size_t d = 0; d < labels.size(); ++d) {
    const int l = views.docs.labels[d];
    if (dt.empty[d]) {
      ++r.empty_documents;
    } else if (l >= 0) {
      labels[d] = views.docs.classes[static_cast<std::size_t>(l)];
    }
  }
  r.summary = topics::update_mot(file.model, dt.theta, labels, options.mot);
  topics::save_mot_model(file.model, file.basis, options.out);
  r.model = file.model;
  r.basis = file.basis;
  r.model_file = options.model;
  r.out = options.out;
  r.source = MotSourceRecord::of(options.source);
  r.rule = options.mot.update;
  r.forgetting = options.mot.forgetting;
  r.document = core::result_document("proprio.mot.update", 1, provenance);
  core::fields_into_json(r, r.document);
  r.message = core::first_line(r.brief());
  return r;
}

MotInfo run_mot_info(const fs::path& model, const core::Provenance& provenance) {
  const topics::MotModelFile f = topics::load_mot_model(model);
  MotInfo out;
  const topics::MotBasis& b = f.basis;
  out.lines.push_back(model.string() + ": " + std::to_string(f.model.num_classes()) +
                      " objects over " + std::to_string(f.model.num_topics()) + " topics, prior " +
                      std::string(core::choice_name(f.model.prior, topics::kMotPriorNames)) +
                      ", theta smoothing " + core::printf_string("%g", f.model.smoothing));
  out.lines.push_back("built on LDA model " + hex(b.lda_checksum) + " (" +
                      std::to_string(b.lda_topics) + " topics, " + std::to_string(b.lda_words) +
                      " words)" +
                      (b.has_vocabulary ? ", vocabulary " + hex(b.vocabulary_checksum) : ""));
  for (const auto& o : f.model.objects) {
    std::ostringstream s;
    s.precision(4);
    s << o.name << ": " << o.views << " views, precision " << o.dirichlet.precision()
      << ", mean theta";
    for (Eigen::Index k = 0; k < o.dirichlet.dim(); ++k) s << ' ' << o.dirichlet.mean()(k);
    if (!o.mixture.components.empty()) {
      s << "; density a mixture of " << o.mixture.num_components()
        << " Dirichlets (weight/precision";
      for (const auto& c : o.mixture.components) {
        s << ' ' << c.weight << '/' << c.dirichlet.precision();
      }
      s << ')';
    }
    out.lines.push_back(s.str());
  }
  out.model_file = model;
  out.file = f;
  out.document = core::result_document("proprio.mot.info", 1, provenance);
  core::fields_into_json(out, out.document);
  out.message = core::first_line(out.brief());
  return out;
}

MotSourceRecord MotSourceRecord::of(const MotSourceOptions& o) {
  return {o.lda_model, o.vocabulary, o.images.empty() ? "episodes" : "images",
          o.images.empty() ? o.episodes : o.images};
}

MotBasisRecord MotBasisRecord::of(const topics::MotBasis& b) {
  return {hex(b.lda_checksum), b.lda_topics, b.lda_words,
          b.has_vocabulary ? core::Json(hex(b.vocabulary_checksum)) : core::Json()};
}

std::vector<MotObjectRecord> MotObjectRecord::of(
    const topics::MotModel& model, const std::vector<topics::DirichletFitSummary>* fits) {
  std::vector<MotObjectRecord> out;
  for (std::size_t c = 0; c < model.objects.size(); ++c) {
    const topics::MotObject& o = model.objects[c];
    MotObjectRecord& r = out.emplace_back();
    r.name = o.name;
    r.views = o.views;
    const Eigen::VectorXd& a = o.dirichlet.alpha();
    r.alpha.assign(a.data(), a.data() + a.size());
    const Eigen::VectorXd m = o.dirichlet.mean();
    r.mean.emplace(m.data(), m.data() + m.size());
    r.precision = o.dirichlet.precision();
    if (!o.mixture.components.empty()) {
      auto& cs = r.components.emplace();
      for (const auto& comp : o.mixture.components) {
        const Eigen::VectorXd& ca = comp.dirichlet.alpha();
        cs.push_back({comp.weight, {ca.data(), ca.data() + ca.size()}, comp.dirichlet.precision()});
      }
    }
    if (fits != nullptr) {
      const topics::DirichletFitSummary& s = (*fits)[c];
      r.fit =
          MotFitRecord{s.converged, topics::to_string(s.stop), s.iterations(), s.log_likelihood};
    }
  }
  return out;
}

std::vector<core::Json> finite_or_null(const std::vector<double>& values) {
  std::vector<core::Json> out;
  out.reserve(values.size());
  for (const double v : values) out.push_back(std::isfinite(v) ? core::Json(v) : core::Json());
  return out;
}

}  // namespace proprio::recognition

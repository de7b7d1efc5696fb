// proprio._proprio.topics: corpora from CSR arrays, online LDA, inference, perplexity, model
// bytes, the Dirichlet and its fit, the Mixture of Topics. Long calls release the GIL.
#include <cstring>

#include "common.hpp"
#include "options.hpp"
#include "proprio/core/random.hpp"
#include "proprio/topics/corpus.hpp"
#include "proprio/topics/corpus_io.hpp"
#include "proprio/topics/dirichlet.hpp"
#include "proprio/topics/dirichlet_fit.hpp"
#include "proprio/topics/inference.hpp"
#include "proprio/topics/lda_model.hpp"
#include "proprio/topics/lda_model_io.hpp"
#include "proprio/topics/mixture_of_topics.hpp"
#include "proprio/topics/mot_model_io.hpp"
#include "proprio/topics/online_lda.hpp"
#include "proprio/topics/perplexity.hpp"

namespace proprio::python {

namespace {

using topics::Corpus;
using topics::LdaModel;

// A corpus from the three arrays of a CSR matrix (scipy.sparse.csr_matrix's indptr, indices,
// data). Zeros are skipped, repeated columns summed; everything is copied into the Corpus.
Corpus corpus_from_csr(const py::handle& indptr_obj, const py::handle& indices_obj,
                       const py::handle& data_obj, std::int64_t num_words) {
  if (num_words < 1 || num_words > topics::kMaxCorpusWords) {
    throw py::value_error("num_words: expected an integer in [1, " +
                          std::to_string(topics::kMaxCorpusWords) + "], got " +
                          std::to_string(num_words));
  }
  const auto indptr = require_array<std::int64_t>(indptr_obj, "indptr", 1);
  if (indptr.shape(0) < 1) throw py::value_error("indptr: expected at least one entry");
  const auto nnz = indptr.at(indptr.shape(0) - 1);
  const auto indices = require_array<std::int32_t>(indices_obj, "indices", 1);
  const auto data = require_array<std::int32_t>(data_obj, "data", 1, {indices.shape(0)});
  if (indptr.at(0) != 0 || nnz != indices.shape(0)) {
    throw py::value_error("indptr: expected to start at 0 and end at len(indices) = " +
                          std::to_string(indices.shape(0)) + ", got " +
                          std::to_string(indptr.at(0)) + " .. " + std::to_string(nnz));
  }
  const auto* p = indptr.data();
  const auto* idx = indices.data();
  const auto* val = data.data();
  Corpus corpus(static_cast<std::int32_t>(num_words));
  std::vector<std::int32_t> words;
  std::vector<std::int32_t> counts;
  const auto rows = indptr.shape(0) - 1;
  for (py::ssize_t r = 0; r < rows; ++r) {
    if (p[r + 1] < p[r]) {
      throw py::value_error("indptr: expected non-decreasing offsets, row " + std::to_string(r));
    }
    words.clear();
    counts.clear();
    for (auto i = p[r]; i < p[r + 1]; ++i) {
      if (val[i] < 0) {
        throw py::value_error("X: expected non-negative counts, got " + std::to_string(val[i]) +
                              " in row " + std::to_string(r));
      }
      if (idx[i] < 0 || idx[i] >= num_words) {
        throw py::value_error("indices: expected column indices in [0, " +
                              std::to_string(num_words) + "), got " + std::to_string(idx[i]) +
                              " in row " + std::to_string(r));
      }
      if (val[i] == 0) continue;
      words.push_back(idx[i]);
      counts.push_back(val[i]);
    }
    corpus.add_document(words, counts);
  }
  return corpus;
}

py::tuple corpus_to_csr(const Corpus& c) {
  py::array_t<std::int64_t> indptr(static_cast<py::ssize_t>(c.num_documents() + 1));
  py::array_t<std::int32_t> indices(static_cast<py::ssize_t>(c.num_entries()));
  py::array_t<std::int32_t> data(static_cast<py::ssize_t>(c.num_entries()));
  auto* p = indptr.mutable_data();
  auto* idx = indices.mutable_data();
  auto* val = data.mutable_data();
  std::int64_t at = 0;
  p[0] = 0;
  for (std::size_t d = 0; d < c.num_documents(); ++d) {
    const auto doc = c.document(d);
    std::memcpy(idx + at, doc.words.data(), doc.size() * sizeof(std::int32_t));
    std::memcpy(val + at, doc.counts.data(), doc.size() * sizeof(std::int32_t));
    at += static_cast<std::int64_t>(doc.size());
    p[d + 1] = at;
  }
  return py::make_tuple(indptr, indices, data);
}

// lambda as a read-only numpy view of the model's memory (K x W, Fortran order), kept alive by
// the model object: no copy.
py::array lambda_view(const py::object& self) {
  auto& model = self.cast<const LdaModel&>();
  const auto k = static_cast<py::ssize_t>(model.lambda.rows());
  const auto w = static_cast<py::ssize_t>(model.lambda.cols());
  const auto s = static_cast<py::ssize_t>(sizeof(double));
  py::array a(py::dtype::of<double>(), {k, w}, {s, s * k}, model.lambda.data(), self);
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

py::bytes model_bytes(const LdaModel& model) {
  return py::bytes(topics::serialize_lda_model(model));
}

LdaModel model_from_bytes(const py::bytes& bytes) {
  const std::string_view view = bytes;
  return topics::parse_lda_model(view, "<bytes>");
}

// The summary as `lda train --json` records it (OnlineLdaSummary::describe names the keys:
// estep_capped, docs_per_s, perplexity_trace as dicts, ...) and its brief line.
py::dict summary_dict(const topics::OnlineLdaSummary& s) {
  auto d = json_to_python(core::fields_to_json(s)).cast<py::dict>();
  d["brief"] = s.brief();
  return d;
}

py::dict fit_summary_dict(const topics::DirichletFitSummary& s) {
  py::dict d;
  d["converged"] = s.converged;
  d["stop"] = topics::to_string(s.stop);
  d["iterations"] = s.iterations();
  d["fixed_point_iterations"] = s.fixed_point_iterations;
  d["newton_iterations"] = s.newton_iterations;
  d["log_likelihood"] = s.log_likelihood;
  d["gradient_max_norm"] = s.gradient_max_norm;
  d["count"] = s.count;
  d["clamped"] = s.clamped;
  d["message"] = s.message;
  d["brief"] = s.brief();
  return d;
}

topics::EStepOptions estep(int max_iterations, double tolerance, bool random_init) {
  topics::EStepOptions e;
  e.max_iterations = max_iterations;
  e.tolerance = tolerance;
  e.init = random_init ? topics::GammaInit::kRandomGamma : topics::GammaInit::kOnes;
  e.validate();
  return e;
}

// theta (D x T float64, rows on the simplex) checked for its shape and NaN, naming "theta".
Eigen::MatrixXd theta_matrix(const py::handle& theta, int topics_expected = -1) {
  return matrix_from_array(theta, "theta", true, topics_expected);
}

py::bytes mot_bytes(const topics::MotModel& model) {
  topics::MotBasis basis;
  basis.lda_topics = model.num_topics();
  basis.lda_words = 1;  // no LDA model recorded (checksum 0); the format needs W >= 1
  return py::bytes(topics::serialize_mot_model(model, basis));
}

py::dict mot_fit_summary(const topics::MotFitSummary& s) {
  py::dict d;
  d["views"] = s.views;
  d["classes"] = s.classes;
  d["topics"] = s.topics;
  d["log_likelihood"] = s.log_likelihood;
  d["kmeans_sse"] = s.kmeans_sse;
  d["refine_rounds"] = s.refine_rounds;
  d["bic"] = s.bic;
  py::list fits;
  for (const auto& f : s.fits) fits.append(fit_summary_dict(f));
  d["fits"] = fits;
  // MotOptions::components > 1: the Dirichlets chosen per object; shared_precision: the shared s.
  std::vector<int> components;
  for (const auto& m : s.mixtures) components.push_back(m.components);
  d["components"] = components;
  if (s.shared) d["shared_precision"] = s.shared->precision;
  d["brief"] = s.brief();
  return d;
}

py::tuple mot_fit_tuple(topics::MotFit fit) {
  auto summary = mot_fit_summary(fit.summary);
  py::array_t<int> assignment(static_cast<py::ssize_t>(fit.assignment.size()));
  std::copy(fit.assignment.begin(), fit.assignment.end(), assignment.mutable_data());
  return py::make_tuple(std::move(fit.model), summary, assignment);
}

}  // namespace

void bind_topics(py::module_& m) {
  py::class_<Corpus>(m, "Corpus",
                     "Bag-of-words documents over num_words words (integer counts), as proprio "
                     "stores them. Built from CSR arrays (copied).")
      .def_static("from_csr", &corpus_from_csr, py::arg("indptr"), py::arg("indices"),
                  py::arg("data"), py::arg("num_words"),
                  "A corpus from a CSR matrix's arrays: indptr int64 (D+1,), indices int32 "
                  "(nnz,), data int32 (nnz,) counts >= 0 (zeros skipped), all C-contiguous. "
                  "ValueError naming the argument otherwise. Copies.")
      .def_static(
          "read",
          [](const py::object& path, const std::string& format) {
            const auto p = to_path(path, "path");
            const auto f = topics::parse_corpus_format(format);
            py::gil_scoped_release release;
            return topics::read_corpus(p, f);
          },
          py::arg("path"), py::arg("format") = "uci",
          "Reads a corpus directory or file: format uci, ldac or mm (as `proprio lda train`).")
      .def("to_csr", &corpus_to_csr,
           "(indptr int64, indices int32, data int32), copies, for scipy.sparse.csr_matrix.")
      .def_property_readonly("num_documents", &Corpus::num_documents)
      .def_property_readonly("num_words", &Corpus::num_words)
      .def_property_readonly("num_tokens", &Corpus::num_tokens)
      .def_property_readonly("vocabulary", &Corpus::vocabulary)
      .def("__len__", &Corpus::num_documents)
      .def("__repr__", [](const Corpus& c) {
        return "Corpus(documents=" + std::to_string(c.num_documents()) +
               ", words=" + std::to_string(c.num_words()) +
               ", tokens=" + std::to_string(c.num_tokens()) + ")";
      });

  py::class_<LdaModel>(m, "LdaModel",
                       "A trained LDA model: lambda (K x W variational topic parameters), the "
                       "priors alpha and eta, and the online schedule's state.")
      .def_property_readonly("lambda_", &lambda_view,
                             "K x W float64, a read-only view of the model's memory (no copy).")
      .def_readonly("alpha", &LdaModel::alpha)
      .def_readonly("eta", &LdaModel::eta)
      .def_readonly("tau0", &LdaModel::tau0)
      .def_readonly("kappa", &LdaModel::kappa)
      .def_readonly("updates", &LdaModel::updates)
      .def_readonly("total_documents", &LdaModel::total_documents)
      .def_readonly("vocabulary", &LdaModel::vocabulary)
      .def_readonly("word_weights", &LdaModel::word_weights,
                    "Empty, or each word's weight in the documents the model learns from and "
                    "reads (infer weighs them itself).")
      .def_property_readonly("num_topics", &LdaModel::num_topics)
      .def_property_readonly("num_words", &LdaModel::num_words)
      .def(
          "topic_word", [](const LdaModel& model) { return array_from_matrix(model.topic_word()); },
          "K x W posterior mean of beta (rows sum to 1); a copy.")
      .def("top_words", &LdaModel::top_words, py::arg("k"), py::arg("n"),
           "The n most probable word ids of topic k.")
      .def_static(
          "from_lambda",
          [](const py::handle& lambda, double alpha, double eta) {
            LdaModel model;
            model.lambda = matrix_from_array(lambda, "lambda");
            model.alpha = alpha;
            model.eta = eta;
            model.validate();
            return model;
          },
          py::arg("lambda_"), py::arg("alpha"), py::arg("eta"),
          "A model from K x W float64 lambda (e.g. scikit-learn's components_, copied) and the "
          "priors, to score or infer with proprio. ValueError when it is not a valid model.")
      .def("to_bytes", &model_bytes, "The model file's bytes (docs/formats/lda-model.md).")
      .def_static("from_bytes", &model_from_bytes, py::arg("data"),
                  "Parses a model file's bytes; ValueError when they are not a valid model.")
      .def(
          "save",
          [](const LdaModel& model, const py::object& path) {
            topics::save_lda_model(model, to_path(path, "path"));
          },
          py::arg("path"), "Writes the model file atomically.")
      .def_static(
          "load",
          [](const py::object& path) { return topics::load_lda_model(to_path(path, "path")); },
          py::arg("path"),
          "Reads a model file: OSError when it cannot be opened, ValueError "
          "with the CLI's message when it is not a valid model.")
      .def("__eq__", [](const LdaModel& a, const LdaModel& b) { return a == b; })
      .def("__repr__",
           [](const LdaModel& model) {
             return "LdaModel(topics=" + std::to_string(model.num_topics()) +
                    ", words=" + std::to_string(model.num_words()) +
                    ", updates=" + std::to_string(model.updates) + ")";
           })
      .def(py::pickle([](const LdaModel& model) { return model_bytes(model); },
                      [](const py::bytes& b) { return model_from_bytes(b); }));

  bind_options<topics::OnlineLdaOptions>(
      m, "OnlineLdaOptions",
      "Options of online LDA (Hoffman, Blei & Bach 2010; `proprio lda train`'s flags).");

  m.def(
      "train_online_lda",
      [](const Corpus& corpus, const topics::OnlineLdaOptions& options, const Corpus* heldout) {
        options.validate();
        topics::OnlineLdaResult result;
        {
          py::gil_scoped_release release;
          result = heldout != nullptr ? topics::train_online_lda(corpus, *heldout, options)
                                      : topics::train_online_lda(corpus, options);
        }
        return py::make_tuple(std::move(result.model), summary_dict(result.summary));
      },
      py::arg("corpus"), py::arg("options"), py::arg("heldout") = nullptr,
      "Trains online LDA on the corpus in order, options.passes times (the GIL is released). "
      "Returns (LdaModel, summary dict). The model does not depend on options.threads.");

  py::class_<topics::OnlineLda>(m, "OnlineLda",
                                "The online learner as a stream consumer: update() with one "
                                "mini-batch after another.")
      .def(py::init([](const topics::OnlineLdaOptions& options, std::int64_t num_words,
                       std::int64_t total_documents) {
             options.validate();
             if (num_words < 1 || num_words > topics::kMaxCorpusWords) {
               throw py::value_error("num_words: expected an integer in [1, " +
                                     std::to_string(topics::kMaxCorpusWords) + "]");
             }
             if (total_documents < 1) throw py::value_error("total_documents: expected >= 1");
             return topics::OnlineLda(options, static_cast<std::int32_t>(num_words),
                                      total_documents);
           }),
           py::arg("options"), py::arg("num_words"), py::arg("total_documents"))
      .def(py::init([](const LdaModel& model, const topics::OnlineLdaOptions& options) {
             options.validate();
             return topics::OnlineLda(model, options);
           }),
           py::arg("model"), py::arg("options"),
           "Continues training `model` (its priors, tau0, kappa and update count are kept).")
      .def(
          "update",
          [](topics::OnlineLda& lda, const Corpus& corpus, std::size_t begin, std::size_t end) {
            if (begin > end || end > corpus.num_documents()) {
              throw py::value_error("begin, end: expected 0 <= begin <= end <= " +
                                    std::to_string(corpus.num_documents()));
            }
            topics::MiniBatchStats s;
            {
              py::gil_scoped_release release;
              s = lda.update(corpus, begin, end);
            }
            py::dict d;
            d["documents"] = s.documents;
            d["tokens"] = s.tokens;
            d["rho"] = s.rho;
            d["estep_iterations"] = s.estep_iterations;
            d["capped"] = s.capped;
            return d;
          },
          py::arg("corpus"), py::arg("begin"), py::arg("end"),
          "One update with documents [begin, end) as the mini-batch (eq B.23-B.24).")
      .def_property_readonly(
          "model", [](const topics::OnlineLda& lda) { return lda.model(); },
          "A copy of the current model.")
      .def_property_readonly("kernel", &topics::OnlineLda::kernel);

  m.def(
      "infer_gamma",
      [](const LdaModel& model, const Corpus& corpus, int max_iterations, double tolerance,
         int threads, std::uint64_t seed, bool random_init) {
        topics::InferenceOptions o;
        o.estep = estep(max_iterations, tolerance, random_init);
        o.threads = threads;
        o.seed = seed;
        o.validate();
        topics::InferenceResult r;
        {
          py::gil_scoped_release release;
          r = topics::infer_topics(model, corpus, o);
        }
        return array_from_matrix(r.gamma);
      },
      py::arg("model"), py::arg("corpus"), py::arg("max_iterations") = 100,
      py::arg("tolerance") = 1e-3, py::arg("threads") = 1, py::arg("seed") = 1,
      py::arg("random_init") = false,
      "D x K variational Dirichlet parameters gamma of each document (eq B.17), the topics "
      "fixed; theta = gamma / gamma.sum(axis=1). A copy. GIL released.");

  m.def(
      "perplexity",
      [](const LdaModel& model, const Corpus& corpus, const std::string& method, int max_iterations,
         double tolerance, int threads, std::uint64_t split_seed) {
        topics::PerplexityOptions o;
        if (method == "bound") {
          o.method = topics::PerplexityMethod::kVariationalBound;
        } else if (method == "completion") {
          o.method = topics::PerplexityMethod::kDocumentCompletion;
        } else {
          throw py::value_error("method: expected 'bound' or 'completion', got '" + method + "'");
        }
        o.estep = estep(max_iterations, tolerance, false);
        o.threads = threads;
        o.split_seed = split_seed;
        o.validate();
        topics::PerplexityResult r;
        {
          py::gil_scoped_release release;
          r = topics::perplexity(model, corpus, o);
        }
        py::dict d;
        d["perplexity"] = r.perplexity;
        d["log_likelihood"] = r.log_likelihood;
        d["tokens"] = r.tokens;
        d["documents"] = r.documents;
        d["seconds"] = r.seconds;
        return d;
      },
      py::arg("model"), py::arg("corpus"), py::arg("method") = "completion",
      py::arg("max_iterations") = 100, py::arg("tolerance") = 1e-3, py::arg("threads") = 1,
      py::arg("split_seed") = 1,
      "Held-out perplexity: 'completion' (document completion, Wallach et al. 2009) or 'bound' "
      "(the variational bound, scikit-learn's perplexity()). Returns a dict with perplexity and "
      "log_likelihood (nats).");

  py::class_<topics::Dirichlet>(m, "Dirichlet", "Dir(alpha) over T >= 2 proportions.")
      .def(py::init([](const py::handle& alpha) {
             const auto a = require_array<double>(alpha, "alpha", 1);
             return topics::Dirichlet(Eigen::Map<const Eigen::VectorXd>(
                 a.data(), static_cast<Eigen::Index>(a.shape(0))));
           }),
           py::arg("alpha"), "alpha: 1-d float64, every entry positive and finite (copied).")
      .def_property_readonly(
          "alpha", [](const topics::Dirichlet& d) { return array_from_vector(d.alpha()); })
      .def_property_readonly("precision", &topics::Dirichlet::precision)
      .def_property_readonly("dim", &topics::Dirichlet::dim)
      .def("mean", [](const topics::Dirichlet& d) { return array_from_vector(d.mean()); })
      .def("mean_log", [](const topics::Dirichlet& d) { return array_from_vector(d.mean_log()); })
      .def(
          "log_density",
          [](const topics::Dirichlet& d, const py::handle& p) {
            const auto m2 = matrix_from_array(p, "p", true, d.dim());
            py::array_t<double> out(static_cast<py::ssize_t>(m2.rows()));
            for (Eigen::Index i = 0; i < m2.rows(); ++i) {
              out.mutable_data()[i] = d.log_density(m2.row(i).transpose());
            }
            return out;
          },
          py::arg("p"), "log Dir(p | alpha) of each row of p (n x T float64), nats.")
      .def(
          "sample",
          [](const topics::Dirichlet& d, int n, std::uint64_t seed) {
            if (n < 0) throw py::value_error("n: expected >= 0");
            core::Rng rng(seed);
            Eigen::MatrixXd logs = d.sample_log(rng, n);
            return array_from_matrix(logs.array().exp().matrix());
          },
          py::arg("n"), py::arg("seed") = 1, "n samples (n x T), seeded.")
      .def("__repr__", [](const topics::Dirichlet& d) {
        return "Dirichlet(dim=" + std::to_string(d.dim()) +
               ", precision=" + std::to_string(d.precision()) + ")";
      });

  m.def(
      "fit_dirichlet",
      [](const py::handle& proportions, double tolerance, int max_iterations, int fixed_point_steps,
         double max_precision, double floor, double sum_tolerance) {
        const auto p = matrix_from_array(proportions, "proportions");
        topics::DirichletFitOptions o;
        o.tolerance = tolerance;
        o.max_iterations = max_iterations;
        o.fixed_point_steps = fixed_point_steps;
        o.max_precision = max_precision;
        o.proportions.floor = floor;
        o.proportions.sum_tolerance = sum_tolerance;
        o.validate();
        auto fit = topics::fit_dirichlet(p, o);
        return py::make_tuple(fit.dirichlet, fit_summary_dict(fit.summary));
      },
      py::arg("proportions"), py::arg("tolerance") = 1e-9, py::arg("max_iterations") = 100,
      py::arg("fixed_point_steps") = 2, py::arg("max_precision") = 1e8,
      py::arg("floor") = topics::kDirichletFloor,
      py::arg("sum_tolerance") = topics::kProportionSumTolerance,
      "Maximum-likelihood Dirichlet (Minka 2003) of n x T proportions (rows on the simplex). "
      "Returns (Dirichlet, summary dict).");

  bind_options<topics::MotOptions>(m, "MotOptions",
                                   "Options of the Mixture of Topics (thesis 7.1, `proprio mot`).");

  py::class_<topics::MotModel>(m, "MotModel",
                               "A Mixture of Topics: one Dirichlet over theta per object.")
      .def_property_readonly("num_classes", &topics::MotModel::num_classes)
      .def_property_readonly("num_topics", &topics::MotModel::num_topics)
      .def_property_readonly("names", &topics::MotModel::names)
      .def_property_readonly(
          "log_prior",
          [](const topics::MotModel& model) { return array_from_vector(model.log_prior()); })
      .def_property_readonly(
          "alphas",
          [](const topics::MotModel& model) {
            Eigen::MatrixXd a(model.num_classes(), model.num_topics());
            for (int c = 0; c < model.num_classes(); ++c)
              a.row(c) = model.objects[c].dirichlet.alpha();
            return array_from_matrix(a);
          },
          "C x T: omega_c of each object (a copy).")
      .def("to_bytes", &mot_bytes, "The MoT model file's bytes (no LDA basis recorded).")
      .def_static(
          "from_bytes",
          [](const py::bytes& b) {
            return topics::parse_mot_model(std::string_view(b), "<bytes>").model;
          },
          py::arg("data"))
      .def_static(
          "load",
          [](const py::object& path) {
            return topics::load_mot_model(to_path(path, "path")).model;
          },
          py::arg("path"), "Reads a MoT model file written by `proprio mot`.")
      .def(py::pickle([](const topics::MotModel& model) { return mot_bytes(model); },
                      [](const py::bytes& b) {
                        return topics::parse_mot_model(std::string_view(b), "<pickle>").model;
                      }));

  m.def(
      "fit_mot",
      [](const py::handle& theta, const py::handle& labels, const std::vector<std::string>& classes,
         const topics::MotOptions& options) {
        const auto t = theta_matrix(theta);
        const auto l = require_array<std::int32_t>(labels, "labels", 1, {t.rows()});
        options.validate();
        const std::vector<int> lv(l.data(), l.data() + l.shape(0));
        topics::MotFit fit;
        {
          py::gil_scoped_release release;
          fit = topics::fit_mot(t, lv, classes, options);
        }
        return mot_fit_tuple(std::move(fit));
      },
      py::arg("theta"), py::arg("labels"), py::arg("classes"), py::arg("options"),
      "Supervised fit (thesis 7.1): theta D x T float64, labels int32 in [0, C) or -1, classes "
      "the C names. Returns (MotModel, summary dict, assignment).");
  m.def(
      "fit_mot_unsupervised",
      [](const py::handle& theta, const topics::MotOptions& options) {
        const auto t = theta_matrix(theta);
        options.validate();
        topics::MotFit fit;
        {
          py::gil_scoped_release release;
          fit = topics::fit_mot_unsupervised(t, options);
        }
        return mot_fit_tuple(std::move(fit));
      },
      py::arg("theta"), py::arg("options"),
      "Unsupervised fit (thesis 7.3.3): k-means over theta, C given or chosen by BIC.");
  m.def(
      "classify_mot",
      [](const topics::MotModel& model, const py::handle& theta) {
        const auto t = theta_matrix(theta, model.num_topics());
        const auto c = topics::classify_mot(model, t);
        py::array_t<int> predicted(static_cast<py::ssize_t>(c.predicted.size()));
        std::copy(c.predicted.begin(), c.predicted.end(), predicted.mutable_data());
        return py::make_tuple(array_from_matrix(c.posterior), array_from_matrix(c.log_score),
                              predicted);
      },
      py::arg("model"), py::arg("theta"),
      "eq 7.3: (posterior D x C, log score D x C, predicted D).");
}

}  // namespace proprio::python

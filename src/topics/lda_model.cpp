#include "proprio/topics/lda_model.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "proprio/core/error.hpp"
#include "proprio/core/text.hpp"
#include "proprio/topics/estep_options.hpp"

namespace proprio::topics {

Eigen::MatrixXd LdaModel::topic_word() const {
  Eigen::MatrixXd beta = lambda;
  for (Eigen::Index k = 0; k < beta.rows(); ++k) beta.row(k) /= beta.row(k).sum();
  return beta;
}

std::vector<int> LdaModel::top_words(int k, int n) const {
  std::vector<int> order(static_cast<std::size_t>(num_words()));
  std::iota(order.begin(), order.end(), 0);
  n = std::clamp(n, 0, num_words());
  std::partial_sort(order.begin(), order.begin() + n, order.end(), [&](int a, int b) {
    const double la = lambda(k, a);
    const double lb = lambda(k, b);
    return la != lb ? la > lb : a < b;
  });
  order.resize(static_cast<std::size_t>(n));
  return order;
}

void LdaModel::validate() const {
  if (lambda.rows() < 1 || lambda.cols() < 1) {
    throw Error("LDA model: no topics or no words (" + std::to_string(lambda.rows()) + " x " +
                std::to_string(lambda.cols()) + ")");
  }
  // Priors and lambda beyond the caps overflow the E-step's sums into NaN (issue 16: infer wrote
  // rows of -nan): such a model is refused, not used.
  if (!(alpha > 0 && alpha <= kMaxLdaPrior)) {
    throw Error("LDA model: alpha = " + core::num(alpha) + " is not in (0, " +
                core::num(kMaxLdaPrior) + "]");
  }
  if (!(eta > 0 && eta <= kMaxLdaPrior)) {
    throw Error("LDA model: eta = " + core::num(eta) + " is not in (0, " + core::num(kMaxLdaPrior) +
                "]");
  }
  if (!(std::isfinite(tau0) && tau0 >= 0)) throw Error("LDA model: tau0 is negative");
  if (!(std::isfinite(kappa) && kappa > 0)) throw Error("LDA model: kappa is not positive");
  if (updates < 0 || total_documents < 0) throw Error("LDA model: negative counts");
  for (Eigen::Index w = 0; w < lambda.cols(); ++w) {
    for (Eigen::Index k = 0; k < lambda.rows(); ++k) {
      const double v = lambda(k, w);
      if (!(v > 0 && v <= kMaxLdaLambda)) {
        throw Error("LDA model: lambda(" + std::to_string(k) + ", " + std::to_string(w) +
                    ") = " + core::num(v) + " is not in (0, 1e100]");
      }
    }
  }
  if (!vocabulary.empty() && static_cast<Eigen::Index>(vocabulary.size()) != lambda.cols()) {
    throw Error("LDA model: " + std::to_string(vocabulary.size()) + " vocabulary words for " +
                std::to_string(lambda.cols()) + " columns");
  }
  if (!word_weights.empty()) {
    if (std::ssize(word_weights) != lambda.cols()) {
      throw Error("LDA model: " + std::to_string(word_weights.size()) + " word weights for " +
                  std::to_string(lambda.cols()) + " words");
    }
    for (std::size_t w = 0; w < word_weights.size(); ++w) {
      if (word_weights[w] < 1 || word_weights[w] > kMaxWordWeight) {
        throw Error("LDA model: the weight of word " + std::to_string(w) + " is " +
                    std::to_string(word_weights[w]) + ", not in [1, " +
                    std::to_string(kMaxWordWeight) + "]");
      }
    }
  }
}

bool LdaModel::operator==(const LdaModel& o) const {
  return lambda.rows() == o.lambda.rows() && lambda.cols() == o.lambda.cols() &&
         lambda == o.lambda && alpha == o.alpha && eta == o.eta && tau0 == o.tau0 &&
         kappa == o.kappa && updates == o.updates && total_documents == o.total_documents &&
         vocabulary == o.vocabulary && word_weights == o.word_weights;
}

void EStepOptions::validate() const {
  if (max_iterations < 1) throw Error("E-step: max_iterations must be at least 1");
  if (!(std::isfinite(tolerance) && tolerance >= 0)) {
    throw Error("E-step: the tolerance must be finite and >= 0");
  }
}

}  // namespace proprio::topics

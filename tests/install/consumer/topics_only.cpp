// A topic-model user: links proprio::topics alone (and so core), never MuJoCo or OpenCV.
#include <cstdio>

#include "proprio/topics/online_lda.hpp"
#include "proprio/topics/synthetic.hpp"

int main() {
  proprio::topics::SyntheticCorpusOptions c;
  c.num_topics = 3;
  c.num_words = 40;
  c.num_documents = 60;
  const auto corpus = proprio::topics::make_synthetic_corpus(c);
  proprio::topics::OnlineLdaOptions o;
  o.num_topics = 3;
  o.batch_size = 20;
  const auto r = proprio::topics::train_online_lda(corpus.corpus, o);
  std::printf("topics: %d topics over %d words\n", r.model.num_topics(),
              static_cast<int>(r.model.lambda.cols()));
  return r.model.num_topics() == 3 ? 0 : 1;
}

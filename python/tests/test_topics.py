"""The topic models' bindings: scikit-learn conventions, determinism, pickling, errors."""

import pickle
import threading
import time

import numpy as np
import pytest
import scipy.sparse as sp
from sklearn.feature_extraction.text import CountVectorizer
from sklearn.model_selection import GridSearchCV
from sklearn.pipeline import Pipeline
from sklearn.utils.estimator_checks import parametrize_with_checks

import proprio
from proprio.topics import (Dirichlet, LatentDirichletAllocation, LdaModel,
                            MixtureOfTopicsClassifier, OnlineLdaOptions, corpus_from_matrix,
                            corpus_to_csr, fit_dirichlet)


# scikit-learn's own checks of an estimator, on small data (each check makes its own). None is
# skipped: all pass.
@parametrize_with_checks([LatentDirichletAllocation(n_components=3, max_iter=2, random_state=0),
                          LatentDirichletAllocation(n_components=2, batch_size=7, n_jobs=2,
                                                    random_state=1)])
def test_sklearn_estimator_checks(estimator, check):
    check(estimator)


def test_recovers_two_topics(counts):
    lda = LatentDirichletAllocation(2, max_iter=20, batch_size=20, random_state=0).fit(counts)
    beta = lda.components_ / lda.components_.sum(axis=1, keepdims=True)
    # Each topic puts almost all its mass on one half of the words.
    halves = np.sort([beta[k, :10].sum() for k in range(2)])
    assert halves[0] < 0.1 and halves[1] > 0.9
    theta = lda.transform(counts)
    assert theta.shape == (60, 2)
    np.testing.assert_allclose(theta.sum(axis=1), 1.0)


def test_dense_and_sparse_give_the_same_model(counts):
    a = LatentDirichletAllocation(3, max_iter=2, random_state=5).fit(counts)
    b = LatentDirichletAllocation(3, max_iter=2, random_state=5).fit(sp.csr_matrix(counts))
    c = LatentDirichletAllocation(3, max_iter=2, random_state=5).fit(sp.csc_matrix(counts))
    assert np.array_equal(a.components_, b.components_)
    assert np.array_equal(a.components_, c.components_)
    assert np.array_equal(a.transform(counts), b.transform(sp.csr_matrix(counts)))


@pytest.mark.parametrize("seed", [0, 7])
def test_same_seed_bit_identical_at_1_and_2_threads(counts, seed):
    one = LatentDirichletAllocation(4, max_iter=3, batch_size=16, n_jobs=1,
                                    random_state=seed).fit(counts)
    two = LatentDirichletAllocation(4, max_iter=3, batch_size=16, n_jobs=2,
                                    random_state=seed).fit(counts)
    assert one.model_.to_bytes() == two.model_.to_bytes()
    assert np.array_equal(one.transform(counts), two.transform(counts))
    other = LatentDirichletAllocation(4, max_iter=3, batch_size=16, random_state=seed + 1)
    assert other.fit(counts).model_.to_bytes() != one.model_.to_bytes()


def test_partial_fit_continues_the_model(counts):
    lda = LatentDirichletAllocation(2, batch_size=20, total_samples=60, random_state=0)
    lda.partial_fit(counts[:30])
    assert lda.n_batch_iter_ == 2
    before = np.array(lda.components_)
    lda.partial_fit(counts[30:])
    assert lda.n_batch_iter_ == 4
    assert not np.array_equal(before, lda.components_)
    with pytest.raises(ValueError, match="features"):
        lda.partial_fit(counts[:, :5])


def test_pickle_goes_through_the_model_bytes(counts, tmp_path):
    lda = LatentDirichletAllocation(3, max_iter=2, random_state=0).fit(counts)
    state = lda.__getstate__()
    assert isinstance(state["_model"], bytes) and "components_" not in state
    again = pickle.loads(pickle.dumps(lda))
    assert again.model_ == lda.model_
    assert np.array_equal(again.transform(counts), lda.transform(counts))
    path = tmp_path / "model.bin"
    lda.model_.save(path)
    assert LdaModel.load(path) == lda.model_
    assert path.read_bytes() == lda.model_.to_bytes()
    assert lda.model_.word_weights == []  # unweighted: format version 1
    assert lda.model_.to_bytes()[8] == 1


def test_components_is_a_read_only_view(counts):
    lda = LatentDirichletAllocation(3, max_iter=1, random_state=0).fit(counts)
    assert not lda.components_.flags.writeable
    assert lda.components_.base is not None  # a view of the model's memory, no copy
    with pytest.raises(ValueError):
        lda.components_[0, 0] = 1.0


def test_perplexity_and_score(counts):
    lda = LatentDirichletAllocation(2, max_iter=10, random_state=0).fit(counts)
    bound = lda.perplexity(counts)
    tokens = counts.sum()
    assert np.isclose(bound, np.exp(-lda.score(counts) / tokens))
    completion = lda.perplexity(counts, method="completion")
    assert 1.0 < completion < 20.0  # 20 words: uniform would be 20
    with pytest.raises(ValueError, match="method"):
        lda.perplexity(counts, method="nope")


def test_pipeline_after_count_vectorizer_and_grid_search():
    docs = ["the arm pushes the red box", "the camera sees the red box move",
            "topics of words in documents", "online variational bayes for topics",
            "the box moves when the arm pushes", "documents are bags of words"] * 4
    pipe = Pipeline([("counts", CountVectorizer()),
                     ("lda", LatentDirichletAllocation(2, max_iter=5, random_state=0))])
    theta = pipe.fit_transform(docs)
    assert theta.shape == (24, 2)
    search = GridSearchCV(pipe, {"lda__n_components": [2, 3]}, cv=2).fit(docs)
    assert search.best_params_["lda__n_components"] in (2, 3)
    names = pipe.get_feature_names_out()
    assert list(names) == ["latentdirichletallocation0", "latentdirichletallocation1"]


def test_get_and_set_params():
    lda = LatentDirichletAllocation(5)
    assert lda.get_params()["n_components"] == 5
    lda.set_params(n_components=7, learning_decay=0.9)
    assert lda.n_components == 7 and lda._options().kappa == 0.9


def test_gil_is_released_while_training():
    rng = np.random.RandomState(0)
    X = sp.csr_matrix(rng.poisson(0.5, size=(3000, 400)))
    lda = LatentDirichletAllocation(30, max_iter=3, random_state=0)
    start = time.perf_counter()
    lda.fit(X)
    alone = time.perf_counter() - start
    assert alone > 0.1  # long enough that a held GIL would show

    worker = threading.Thread(target=lambda: LatentDirichletAllocation(
        30, max_iter=3, random_state=0).fit(X))
    longest = 0.0
    last = time.perf_counter()
    worker.start()
    while worker.is_alive():
        now = time.perf_counter()
        longest = max(longest, now - last)
        last = now
        time.sleep(0.001)
    worker.join()
    # With the GIL held for the whole training the main thread would stall for about `alone`.
    assert longest < alone / 2


# -- bad input: ValueError naming the argument, never a crash --

def test_negative_and_nan_counts_are_value_errors(counts):
    lda = LatentDirichletAllocation(2)
    bad = sp.csr_matrix(counts).astype(np.float64)
    bad.data[3] = -1
    with pytest.raises(ValueError, match="Negative|non-negative"):
        lda.fit(bad)
    with pytest.raises(ValueError, match="X: expected non-negative counts"):
        corpus_from_matrix(bad)
    nan = counts.astype(float)
    nan[0, 0] = np.nan
    with pytest.raises(ValueError, match="NaN"):
        lda.fit(nan)
    with pytest.raises(ValueError, match="X: expected finite"):
        corpus_from_matrix(nan)


def test_bad_parameters_name_the_parameter(counts):
    with pytest.raises(ValueError, match="n_components=0"):
        LatentDirichletAllocation(0).fit(counts)
    with pytest.raises(ValueError, match="learning_decay=0.3"):
        LatentDirichletAllocation(2, learning_decay=0.3).fit(counts)
    with pytest.raises(ValueError, match="batch_size"):
        LatentDirichletAllocation(2, batch_size="many").fit(counts)
    with pytest.raises(ValueError, match="n_jobs"):
        LatentDirichletAllocation(2, n_jobs=0).fit(counts)


def test_low_level_arrays_are_checked(counts):
    from proprio.topics import Corpus
    X = sp.csr_matrix(counts)
    indptr = X.indptr.astype(np.int64)
    indices = X.indices.astype(np.int32)
    data = X.data.astype(np.int32)
    c = Corpus.from_csr(indptr, indices, data, 20)
    assert c.num_tokens == counts.sum()
    assert (corpus_to_csr(c) != X).nnz == 0
    with pytest.raises(ValueError, match="indices: expected a 1-d C-contiguous int32 array, got dtype float64"):
        Corpus.from_csr(indptr, indices.astype(np.float64), data, 20)
    with pytest.raises(ValueError, match="data: .*non-contiguous"):
        Corpus.from_csr(indptr, indices, np.repeat(data, 2)[::2], 20)
    with pytest.raises(ValueError, match="data: expected size"):
        Corpus.from_csr(indptr, indices, data[:-1], 20)
    with pytest.raises(ValueError, match="indices: expected column indices in"):
        Corpus.from_csr(indptr, indices, data, 5)
    with pytest.raises(ValueError, match="indptr: expected a 1-d"):
        Corpus.from_csr(indptr.reshape(1, -1), indices, data, 20)


def test_options_bound_from_their_description():
    o = OnlineLdaOptions(topics=4, kappa=0.8)
    assert o.topics == 4 and o.kappa == 0.8 and o.batch == 256
    assert "OnlineLdaOptions(topics=4" in repr(o)
    assert pickle.loads(pickle.dumps(o)) == o
    names = [f["name"] for f in OnlineLdaOptions.fields()]
    assert names[:3] == ["topics", "batch", "tau0"]
    assert "Number of topics K" in OnlineLdaOptions.topics.__doc__
    with pytest.raises(ValueError, match=r"OnlineLdaOptions.topics must be in \[1, 100000\]"):
        OnlineLdaOptions(topics=0)
    with pytest.raises(ValueError, match="OnlineLdaOptions.kappa must be a number"):
        o.kappa = "fast"
    with pytest.raises(ValueError, match="OnlineLdaOptions.passes must be an integer"):
        o.passes = 2.5
    with pytest.raises(ValueError, match="unknown option 'topcs'"):
        OnlineLdaOptions(topcs=3)


def test_files_that_cannot_be_opened_are_os_errors(tmp_path):
    with pytest.raises(FileNotFoundError):
        LdaModel.load(tmp_path / "missing.bin")
    bad = tmp_path / "bad.bin"
    bad.write_bytes(b"not a model at all, just some bytes")
    with pytest.raises(ValueError) as info:
        LdaModel.load(bad)
    assert str(bad) in str(info.value) and "\n" not in str(info.value)
    with pytest.raises(FileNotFoundError):
        proprio.topics.read_corpus(tmp_path / "nothing-here")


# -- the Dirichlet fit and the Mixture of Topics --

def test_dirichlet_fit_recovers_alpha():
    alpha = np.array([2.0, 5.0, 1.0])
    samples = Dirichlet(alpha).sample(4000, seed=3)
    fitted, summary = fit_dirichlet(samples)
    assert summary["converged"]
    np.testing.assert_allclose(fitted.alpha, alpha, rtol=0.1)
    assert np.all(np.isfinite(fitted.log_density(samples[:5])))


def test_mixture_of_topics_classifier():
    a = Dirichlet(np.array([8.0, 1.0, 1.0])).sample(60, seed=1)
    b = Dirichlet(np.array([1.0, 1.0, 8.0])).sample(60, seed=2)
    theta = np.vstack([a, b])
    y = np.array(["mug"] * 60 + ["box"] * 60)
    clf = MixtureOfTopicsClassifier().fit(theta, y)
    assert list(clf.classes_) == ["box", "mug"]
    assert clf.score(theta, y) > 0.95
    proba = clf.predict_proba(theta)
    np.testing.assert_allclose(proba.sum(axis=1), 1.0)
    again = pickle.loads(pickle.dumps(clf))
    assert np.array_equal(again.predict_proba(theta), proba)
    nan = theta.copy()
    nan[4, 1] = np.nan
    with pytest.raises(ValueError, match="theta"):
        clf.predict(nan)
    off = theta.copy()
    off[2] *= 2
    with pytest.raises(ValueError, match="theta"):
        clf.predict(off)
    with pytest.raises(ValueError, match="theta"):
        clf.predict(theta[:, :2])
    with pytest.raises(ValueError, match="prior"):
        MixtureOfTopicsClassifier(prior="flat").fit(theta, y)

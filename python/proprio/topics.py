"""proprio.topics: topic models with scikit-learn's conventions.

    LatentDirichletAllocation   online LDA (Hoffman, Blei & Bach 2010) as a scikit-learn
                                transformer: fit, partial_fit, transform, fit_transform,
                                perplexity, score, components_, get_params/set_params; dense
                                arrays or scipy.sparse matrices of non-negative counts
    MixtureOfTopicsClassifier   the thesis's Mixture of Topics (7.1) as a classifier over theta:
                                fit, predict, predict_proba
    fit_dirichlet, Dirichlet    Minka's maximum-likelihood Dirichlet fit
    Corpus, LdaModel, OnlineLdaOptions, train_online_lda, OnlineLda, infer_gamma, perplexity,
    MotModel, MotOptions, fit_mot, fit_mot_unsupervised, classify_mot
                                the library's own calls, for those who want them

Counts: proprio's corpora hold integer counts. Float input is rounded to the nearest integer
(np.rint) when it is turned into a corpus, so values below 0.5 count as absent.

Copies: X is copied once into the library's corpus (CSR arrays are converted to int64/int32 and
copied); transform's theta and components_ are new arrays / views: components_ is a read-only
view of the model's memory (no copy), LdaModel.topic_word() a copy.

Determinism: the same random_state (an int) gives a bit-identical model at any n_jobs.
"""

from __future__ import annotations

import numbers
import os

import numpy as np
import scipy.sparse as sp
from sklearn.base import (BaseEstimator, ClassifierMixin, ClassNamePrefixFeaturesOutMixin,
                          TransformerMixin)
from sklearn.utils import check_random_state
from sklearn.utils.validation import check_array, check_is_fitted

from . import _proprio

_t = _proprio.topics

Corpus = _t.Corpus
LdaModel = _t.LdaModel
OnlineLdaOptions = _t.OnlineLdaOptions
OnlineLda = _t.OnlineLda
train_online_lda = _t.train_online_lda
infer_gamma = _t.infer_gamma
perplexity = _t.perplexity
Dirichlet = _t.Dirichlet
MotModel = _t.MotModel
MotOptions = _t.MotOptions
fit_mot = _t.fit_mot
fit_mot_unsupervised = _t.fit_mot_unsupervised
classify_mot = _t.classify_mot

_MAX_COUNT = np.iinfo(np.int32).max


def corpus_from_matrix(X, name: str = "X") -> Corpus:
    """A proprio Corpus (one document per row) from a dense array or a scipy.sparse matrix of
    non-negative counts. Floats are rounded to the nearest integer; NaN, infinity or negative
    values raise ValueError naming `name`. The data are copied."""
    if sp.issparse(X):
        X = sp.csr_matrix(X)
        data = X.data
    else:
        X = np.asarray(X)
        if X.ndim != 2:
            raise ValueError(f"{name}: expected a 2-d array of counts, got {X.ndim} dimensions")
        data = X
    if data.dtype.kind not in "biuf":
        raise ValueError(f"{name}: expected numeric counts, got dtype {data.dtype}")
    if data.dtype.kind == "f":
        if not np.all(np.isfinite(data)):
            raise ValueError(f"{name}: expected finite counts, got NaN or infinity")
    if data.size and data.min() < 0:
        raise ValueError(f"{name}: expected non-negative counts, got {data.min()}")
    if data.size and data.max() > _MAX_COUNT:
        raise ValueError(f"{name}: expected counts below 2**31, got {data.max()}")
    if not sp.issparse(X):
        X = sp.csr_matrix(X)
    if X.shape[1] < 1:
        raise ValueError(f"{name}: expected at least one column (word)")
    counts = np.rint(X.data).astype(np.int32) if X.data.dtype.kind == "f" else \
        X.data.astype(np.int32)
    return Corpus.from_csr(np.ascontiguousarray(X.indptr, dtype=np.int64),
                           np.ascontiguousarray(X.indices, dtype=np.int32),
                           np.ascontiguousarray(counts), X.shape[1])


def corpus_to_csr(corpus: Corpus) -> sp.csr_matrix:
    """The corpus as a scipy.sparse CSR matrix of int32 counts (copied)."""
    indptr, indices, data = corpus.to_csr()
    return sp.csr_matrix((data, indices, indptr),
                         shape=(corpus.num_documents, corpus.num_words))


def read_corpus(path, format: str = "uci") -> sp.csr_matrix:
    """Reads a corpus (uci, ldac or mm, as `proprio lda train`) into a CSR matrix. OSError when
    it cannot be opened, ValueError (with file and line) when its content is bad."""
    return corpus_to_csr(Corpus.read(os.fspath(path), format))


def _threads(n_jobs) -> int:
    if n_jobs is None:
        return 1
    if isinstance(n_jobs, bool) or not isinstance(n_jobs, numbers.Integral) or n_jobs == 0:
        raise ValueError(f"n_jobs: expected None, -1 or a positive integer, got {n_jobs!r}")
    n = int(n_jobs)
    if n < 0:
        n = max(1, (os.cpu_count() or 1) + 1 + n)
    return min(n, 256)


def _seed(random_state) -> int:
    if isinstance(random_state, numbers.Integral) and not isinstance(random_state, bool):
        if random_state < 0:
            raise ValueError(f"random_state: expected a non-negative integer, got {random_state}")
        return int(random_state)
    return int(check_random_state(random_state).randint(np.iinfo(np.int32).max))


class LatentDirichletAllocation(ClassNamePrefixFeaturesOutMixin, TransformerMixin, BaseEstimator):
    """Online variational LDA (Hoffman, Blei & Bach 2010; thesis B.1.2) run by proprio's C++
    engine, with scikit-learn's interface and parameter names.

    Parameters are those of sklearn.decomposition.LatentDirichletAllocation in online mode:
    n_components (K), doc_topic_prior (alpha; None: 1/K), topic_word_prior (eta; None: 1/K),
    learning_decay (kappa), learning_offset (tau0), max_iter (passes over X in fit),
    batch_size, total_samples (D of partial_fit's updates), mean_change_tol and
    max_doc_update_iter (the per-document E-step), n_jobs (threads: the model does not depend on
    it) and random_state (an int for a reproducible, bit-identical model).

    Input: X of shape (n_samples, n_features), non-negative counts, dense or scipy.sparse; floats
    are rounded to integers. The GIL is released while the engine trains or infers.
    """

    def __init__(self, n_components=10, *, doc_topic_prior=None, topic_word_prior=None,
                 learning_decay=0.7, learning_offset=10.0, max_iter=10, batch_size=128,
                 total_samples=1e6, mean_change_tol=1e-3, max_doc_update_iter=100,
                 n_jobs=None, random_state=None):
        self.n_components = n_components
        self.doc_topic_prior = doc_topic_prior
        self.topic_word_prior = topic_word_prior
        self.learning_decay = learning_decay
        self.learning_offset = learning_offset
        self.max_iter = max_iter
        self.batch_size = batch_size
        self.total_samples = total_samples
        self.mean_change_tol = mean_change_tol
        self.max_doc_update_iter = max_doc_update_iter
        self.n_jobs = n_jobs
        self.random_state = random_state

    # -- parameters -> the library's options, each error naming the scikit-learn parameter --
    _FIELDS = (("n_components", "topics"), ("batch_size", "batch"), ("learning_offset", "tau0"),
               ("learning_decay", "kappa"), ("max_iter", "passes"),
               ("max_doc_update_iter", "estep_max_iterations"),
               ("mean_change_tol", "estep_tolerance"))

    def _options(self) -> OnlineLdaOptions:
        o = OnlineLdaOptions()
        for param, field in self._FIELDS:
            value = getattr(self, param)
            try:
                setattr(o, field, value)
            except ValueError as e:
                raise ValueError(f"{param}={value!r}: {e}") from None
        for param, field in (("doc_topic_prior", "alpha"), ("topic_word_prior", "eta")):
            value = getattr(self, param)
            if value is None:
                continue
            if isinstance(value, numbers.Real) and not value > 0:
                raise ValueError(f"{param}={value!r}: must be > 0 (or None for 1/K)")
            try:
                setattr(o, field, value)
            except ValueError as e:
                raise ValueError(f"{param}={value!r}: {e}") from None
        o.threads = _threads(self.n_jobs)
        o.seed = _seed(self.random_state)
        return o

    def _check_X(self, X, reset: bool, where: str) -> Corpus:
        X = self._validate_data(X, reset=reset, accept_sparse="csr", dtype="numeric")
        if X.dtype.kind == "f" and X.dtype != np.float32:
            X = X.astype(np.float64, copy=False)
        return corpus_from_matrix(X, "X")

    def _set_model(self, model: LdaModel) -> None:
        self._model = model
        self.components_ = model.lambda_
        self.n_batch_iter_ = model.updates
        self.doc_topic_prior_ = model.alpha
        self.topic_word_prior_ = model.eta

    @property
    def _n_features_out(self):
        return self.components_.shape[0]

    def fit(self, X, y=None):
        """Trains a new model on X (max_iter passes, mini-batches of batch_size rows in order,
        D = n_samples). Returns self."""
        options = self._options()
        corpus = self._check_X(X, reset=True, where="fit")
        model, summary = train_online_lda(corpus, options)
        self._set_model(model)
        self.n_iter_ = options.passes
        self.training_summary_ = summary
        return self

    def partial_fit(self, X, y=None):
        """One online pass over X in mini-batches of batch_size, continuing the model (a new one
        on the first call, with D = total_samples). Returns self."""
        first = not hasattr(self, "_model")
        options = self._options()
        corpus = self._check_X(X, reset=first, where="partial_fit")
        if first:
            total = self.total_samples
            if not isinstance(total, numbers.Real) or not total >= 1:
                raise ValueError(f"total_samples={total!r}: must be >= 1")
            lda = OnlineLda(options, corpus.num_words, int(total))
            self.n_iter_ = 0
        else:
            if corpus.num_words != self._model.num_words:
                raise ValueError(f"X: expected {self._model.num_words} features, got "
                                 f"{corpus.num_words}")
            lda = OnlineLda(self._model, options)
        n = corpus.num_documents
        for begin in range(0, n, options.batch):
            lda.update(corpus, begin, min(n, begin + options.batch))
        self._set_model(lda.model)
        self.n_iter_ += 1
        return self

    def transform(self, X):
        """Topic proportions of each row, E[theta] (n_samples x n_components, rows sum to 1; an
        empty row gets uniform proportions), the topics held fixed."""
        check_is_fitted(self)
        corpus = self._check_X(X, reset=False, where="transform")
        gamma = infer_gamma(self._model, corpus, max_iterations=self.max_doc_update_iter,
                            tolerance=self.mean_change_tol, threads=_threads(self.n_jobs))
        gamma /= gamma.sum(axis=1, keepdims=True)
        return gamma

    def perplexity(self, X, method: str = "bound") -> float:
        """Perplexity of X: 'bound' (scikit-learn's: exp(-variational bound / tokens)) or
        'completion' (document completion, the held-out measure of bench/bench_topics.py)."""
        check_is_fitted(self)
        corpus = self._check_X(X, reset=False, where="perplexity")
        return _t.perplexity(self._model, corpus, method=method,
                             max_iterations=self.max_doc_update_iter,
                             tolerance=self.mean_change_tol,
                             threads=_threads(self.n_jobs))["perplexity"]

    def score(self, X, y=None) -> float:
        """The variational lower bound on log p(X) (nats), as scikit-learn's score()."""
        check_is_fitted(self)
        corpus = self._check_X(X, reset=False, where="score")
        return _t.perplexity(self._model, corpus, method="bound",
                             max_iterations=self.max_doc_update_iter,
                             tolerance=self.mean_change_tol,
                             threads=_threads(self.n_jobs))["log_likelihood"]

    @property
    def model_(self) -> LdaModel:
        """The trained proprio LdaModel (save() it for `proprio lda infer`)."""
        check_is_fitted(self)
        return self._model

    def _more_tags(self):
        return {"requires_positive_X": True, "preserves_dtype": [np.float64]}

    # Pickling goes through the model file's bytes (docs/formats/lda-model.md).
    def __getstate__(self):
        state = super().__getstate__()
        state = dict(state)
        if "_model" in state:
            state["_model"] = state["_model"].to_bytes()
            state.pop("components_", None)
        return state

    def __setstate__(self, state):
        state = dict(state)
        model = state.pop("_model", None)
        super().__setstate__(state)
        if model is not None:
            self._set_model(LdaModel.from_bytes(model))


def fit_dirichlet(proportions, **options):
    """Maximum-likelihood Dirichlet (Minka 2003) of n x T proportions (rows on the simplex).
    Options: tolerance, max_iterations, fixed_point_steps, max_precision, floor, sum_tolerance.
    Returns (Dirichlet, summary dict)."""
    p = check_array(proportions, dtype=np.float64, order="C", input_name="proportions")
    try:
        return _t.fit_dirichlet(p, **options)
    except ValueError as e:
        raise ValueError(f"proportions: {e}") from None


def _theta(theta):
    return check_array(theta, dtype=np.float64, order="C", input_name="theta")


class MixtureOfTopicsClassifier(ClassifierMixin, BaseEstimator):
    """The Mixture of Topics (thesis 7.1): a Dirichlet Dir(theta | omega_c) per class, fitted by
    maximum likelihood, and Bayes over the classes (eq 7.3). X is theta: n_samples x T topic
    proportions (rows on the simplex, e.g. LatentDirichletAllocation.transform's output).

    prior: 'views' (p(c) proportional to the training views of c) or 'uniform'.
    """

    def __init__(self, prior="views"):
        self.prior = prior

    def _options(self) -> MotOptions:
        try:
            return MotOptions(prior=self.prior)
        except ValueError as e:
            raise ValueError(f"prior={self.prior!r}: {e}") from None

    def fit(self, X, y):
        """Fits one Dirichlet per class (each class needs at least 2 rows)."""
        theta = _theta(X)
        if y is None:
            raise ValueError("y: expected the class of every row of theta")
        y = np.asarray(y)
        if y.shape != (theta.shape[0],):
            raise ValueError(f"y: expected shape ({theta.shape[0]},), got {y.shape}")
        self.classes_, labels = np.unique(y, return_inverse=True)
        names = [str(c) for c in self.classes_]
        try:
            model, summary, _ = fit_mot(theta, labels.astype(np.int32), names, self._options())
        except ValueError as e:
            raise ValueError(f"theta: {e}") from None
        self.model_ = model
        self.fit_summary_ = summary
        self.n_features_in_ = theta.shape[1]
        return self

    def predict_proba(self, X):
        """p(c | theta) of each row (eq 7.3), n_samples x n_classes."""
        check_is_fitted(self)
        theta = _theta(X)
        if theta.shape[1] != self.n_features_in_:
            raise ValueError(f"theta: expected {self.n_features_in_} columns, got {theta.shape[1]}")
        try:
            posterior, _, _ = classify_mot(self.model_, theta)
        except ValueError as e:
            raise ValueError(f"theta: {e}") from None
        return posterior

    def predict_log_proba(self, X):
        return np.log(self.predict_proba(X))

    def predict(self, X):
        """The most probable class of each row."""
        return self.classes_[np.argmax(self.predict_proba(X), axis=1)]


__all__ = ["LatentDirichletAllocation", "MixtureOfTopicsClassifier", "fit_dirichlet", "Dirichlet",
           "Corpus", "LdaModel", "OnlineLdaOptions", "OnlineLda", "train_online_lda",
           "infer_gamma", "perplexity", "MotModel", "MotOptions", "fit_mot",
           "fit_mot_unsupervised", "classify_mot", "corpus_from_matrix", "corpus_to_csr",
           "read_corpus"]

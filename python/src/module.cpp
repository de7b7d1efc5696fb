// The extension proprio._proprio: one submodule per library module; the pure-Python package
// proprio (python/proprio) re-exports them with scikit-learn-style wrappers.
#include "common.hpp"

PYBIND11_MODULE(_proprio, m) {
  namespace p = proprio::python;
  m.doc() = "proprio's C++ library (the compiled part of the proprio package).";
  auto core = m.def_submodule("core", "Version, data directory, errors.");
  p::bind_core(core);
  auto topics = m.def_submodule("topics", "Corpora, online LDA, Dirichlet, Mixture of Topics.");
  p::bind_topics(topics);
  auto features = m.def_submodule("features", "Local features and visual vocabularies.");
  p::bind_features(features);
  auto geometry = m.def_submodule("geometry", "Pinhole cameras: K, R, t, P.");
  p::bind_geometry(geometry);
  auto episode = m.def_submodule("episode", "Recorded interactions read as arrays.");
  p::bind_episode(episode);
  auto vision = m.def_submodule("segmentation", "Motion-Likelihood segmentation of episodes.");
  p::bind_vision(vision);
  auto sim = m.def_submodule("sim", "The simulated world and robot, cameras.");
  p::bind_sim(sim);
  auto planning = m.def_submodule("planning", "Push planning options.");
  p::bind_planning(planning);
  auto loop = m.def_submodule("loop", "Look, plan, push: `proprio push` as a call.");
  p::bind_loop(loop);
}

// proprio._proprio.features: local features of images, k-means vocabularies, quantization.
#include <cstring>

#include "common.hpp"
#include "options.hpp"
#include "proprio/core/provenance.hpp"
#include "proprio/features/extraction.hpp"
#include "proprio/features/kmeans.hpp"
#include "proprio/features/vocabulary.hpp"
#include "proprio/features/vocabulary_build.hpp"

namespace proprio::python {

namespace {

using features::Vocabulary;

// An N x D float32 C-contiguous array as a cv::Mat header over its memory (no copy; the caller
// keeps the array alive for the call).
cv::Mat descriptor_view(const py::handle& obj, const char* name, int dimension = -1) {
  const auto a = require_array<float>(obj, name, 2, {-1, dimension});
  return cv::Mat(static_cast<int>(a.shape(0)), static_cast<int>(a.shape(1)), CV_32F,
                 const_cast<float*>(a.data()));
}

py::array_t<float> array_from_descriptors(const cv::Mat& m) {
  py::array_t<float> out({static_cast<py::ssize_t>(m.rows), static_cast<py::ssize_t>(m.cols)});
  for (int r = 0; r < m.rows; ++r) {
    std::memcpy(out.mutable_data(r, 0), m.ptr<float>(r), m.cols * sizeof(float));
  }
  return out;
}

py::dict kmeans_summary(const features::KmeansSummary& s) {
  py::dict d;
  d["iterations"] = s.iterations;
  d["cost"] = s.cost;
  d["seconds"] = s.seconds;
  d["termination"] = s.termination;
  d["empty_clusters_reseeded"] = s.empty_clusters_reseeded;
  return d;
}

}  // namespace

void bind_features(py::module_& m) {
  bind_options<features::ExtractOptions>(
      m, "ExtractOptions",
      "Which local features make the words (thesis 6.1.1, 7.3.3): dense SIFT on a grid or SIFT at "
      "interest points; the flags of `vocab build`, `vocab quantize`, `recognize`.");
  bind_options<features::KmeansOptions>(
      m, "KmeansOptions", "k-means of descriptors into a vocabulary (`vocab build`).");

  py::class_<Vocabulary>(m, "Vocabulary",
                         "A visual vocabulary (thesis 6.1.2): K words in descriptor space.")
      .def(py::init([](const py::handle& words) {
             return Vocabulary(descriptor_view(words, "words").clone());
           }),
           py::arg("words"), "From K x D float32 words (copied).")
      .def_property_readonly("size", &Vocabulary::size)
      .def_property_readonly("dimension", &Vocabulary::dimension)
      .def_property_readonly(
          "words", [](const Vocabulary& v) { return array_from_descriptors(v.words()); },
          "K x D float32 (a copy).")
      .def(
          "quantize",
          [](const Vocabulary& v, const py::handle& descriptors, int threads) {
            const auto array = py::reinterpret_borrow<py::object>(descriptors);
            const cv::Mat d = descriptor_view(array, "descriptors", v.dimension());
            std::vector<int> words;
            {
              py::gil_scoped_release release;
              words = v.quantize(d, threads);
            }
            py::array_t<std::int32_t> out(static_cast<py::ssize_t>(words.size()));
            std::copy(words.begin(), words.end(), out.mutable_data());
            return out;
          },
          py::arg("descriptors"), py::arg("threads") = 1,
          "The nearest word of every row of N x D float32 descriptors (read in place, no copy): "
          "int32 word ids. GIL released.")
      .def(
          "save",
          [](const Vocabulary& v, const py::object& path) {
            const core::Provenance p = python_provenance(std::nullopt);
            features::write_vocabulary(to_path(path, "path"), v, p);
          },
          py::arg("path"), "Writes the vocabulary file atomically (docs/formats/vocabulary.md).")
      .def_static(
          "load",
          [](const py::object& path) { return features::read_vocabulary(to_path(path, "path")); },
          py::arg("path"), "Reads a vocabulary file (OSError when it cannot be opened).")
      .def("__repr__", [](const Vocabulary& v) {
        return "Vocabulary(size=" + std::to_string(v.size()) +
               ", dimension=" + std::to_string(v.dimension()) + ")";
      });

  m.def(
      "build_vocabulary",
      [](const py::handle& descriptors, const features::KmeansOptions& options) {
        const auto array = py::reinterpret_borrow<py::object>(descriptors);
        const cv::Mat d = descriptor_view(array, "descriptors");
        options.validate();
        auto r = [&] {
          py::gil_scoped_release release;
          return features::build_vocabulary(d, options);
        }();
        return py::make_tuple(std::move(r.vocabulary), kmeans_summary(r.summary));
      },
      py::arg("descriptors"), py::arg("options"),
      "k-means of N x D float32 descriptors (read in place) into options.words words. Returns "
      "(Vocabulary, summary dict). GIL released.");

  m.def(
      "build_vocabulary_from_images",
      [](const py::object& images, const py::object& out, int per_image,
         const features::ExtractOptions& extract, const features::KmeansOptions& kmeans) {
        features::VocabularyBuildOptions o;
        o.images = to_path(images, "images");
        if (!out.is_none()) o.out = to_path(out, "out");
        o.per_image = per_image;
        o.features = extract;
        o.kmeans = kmeans;
        o.validate();
        const auto provenance = python_provenance(kmeans.seed);
        auto r = [&] {
          py::gil_scoped_release release;
          return features::run_vocabulary_build(o, provenance);
        }();
        auto s = kmeans_summary(r.kmeans);
        s["images"] = r.images;
        s["classes"] = r.classes;
        s["descriptors"] = r.descriptors;
        s["brief"] = r.brief();
        return py::make_tuple(std::move(r.vocabulary), s);
      },
      py::arg("images"), py::arg("out") = py::none(), py::arg("per_image") = 100,
      py::arg("features") = features::VocabularyBuildOptions::sift_extraction(),
      py::arg("kmeans") = features::KmeansOptions{},
      "`proprio vocab build` as a call: the features of a folder-per-class image set, sampled "
      "per image, k-means into words; written to `out` when given. Returns (Vocabulary, "
      "summary dict).");

  m.def(
      "extract_features",
      [](const py::handle& image, const features::ExtractOptions& options, const py::object& mask) {
        const cv::Mat bgr = bgr_from_rgb_array(image, "image");
        cv::Mat m8;
        if (!mask.is_none()) {
          const auto a = require_array<std::uint8_t>(mask, "mask", 2, {bgr.rows, bgr.cols});
          m8 = cv::Mat(bgr.rows, bgr.cols, CV_8U, const_cast<std::uint8_t*>(a.data())).clone();
        }
        options.validate();
        features::Features f;
        {
          py::gil_scoped_release release;
          f = features::extract_features(bgr, options, m8);
        }
        py::array_t<float> points({static_cast<py::ssize_t>(f.size()), py::ssize_t{2}});
        for (int i = 0; i < f.size(); ++i) {
          points.mutable_at(i, 0) = f.keypoints[i].pt.x;
          points.mutable_at(i, 1) = f.keypoints[i].pt.y;
        }
        cv::Mat d =
            f.descriptors.empty() ? cv::Mat(0, features::kDescriptorLength, CV_32F) : f.descriptors;
        return py::make_tuple(points, array_from_descriptors(d));
      },
      py::arg("image"), py::arg("options") = features::ExtractOptions{},
      py::arg("mask") = py::none(),
      "Local features of an H x W x 3 uint8 RGB (or H x W grey) image, only where the optional "
      "H x W uint8 mask is non-zero. Returns (points N x 2 float32 pixels (x, y), descriptors "
      "N x 128 float32). The image is copied (RGB -> BGR).");
}

}  // namespace proprio::python

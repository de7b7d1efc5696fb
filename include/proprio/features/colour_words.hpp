#pragma once
// Colour words: one word a feature for the colour round its keypoint, beside its SIFT word.
//
// The thesis's words are grey-level SIFT (6.1.1), blind to colour, and they change when an object
// turns or falls over; the colour of an object's surface does not. Each feature's patch colour is
// quantised on a fixed grid in HSV (no training: the same words for every run), as the colour
// names and hue histograms of van de Weijer & Schmid ("Coloring local feature extraction", ECCV
// 2006) and van de Sande et al. (TPAMI 2010) add colour to SIFT's bag of words: chromatic colours
// by hue and saturation, the achromatic ones (saturation below `grey_below`) by brightness alone,
// because their hue is noise. Written here: OpenCV converts the colours but has no such words.
#include <cstdint>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "proprio/core/fields.hpp"
#include "proprio/features/features.hpp"
#include "proprio/features/vocabulary.hpp"

namespace proprio::features {

struct ColourWordOptions {
  int hue_bins = 12;          ///< chromatic words: hue bins (30 degrees each)
  int saturation_levels = 2;  ///< ... times saturation levels between grey_below and 1
  int grey_levels = 4;        ///< achromatic words: brightness (HSV value) levels
  double grey_below = 0.25;   ///< saturation (0-1) below which a colour is achromatic
  int radius = 3;             ///< the patch: the mean colour of a (2 radius + 1) px square

  /// hue_bins * saturation_levels + grey_levels.
  [[nodiscard]] int count() const { return hue_bins * saturation_levels + grey_levels; }
  /// Throws Error naming the first option out of its bounds.
  void validate() const;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.hue_bins, {"hue_bins", "Colour words: hue bins", core::between(1, 360)});
    v(self.saturation_levels,
      {"saturation_levels", "Colour words: saturation levels of a hue", core::between(1, 16)});
    v(self.grey_levels,
      {"grey_levels", "Colour words: brightness levels of the greys", core::between(1, 64)});
    v(self.grey_below, {"grey_below", "Colour words: saturation (0-1) below which a colour is grey",
                        core::between(0, 1)});
    v(self.radius,
      {"radius", "Colour words: half side of the patch averaged, px", core::between(0, 64)});
  }
};

/// The colour word (0..options.count()-1) of each keypoint of `image` (8-bit BGR; grey images give
/// grey words only): the mean colour of the square patch round the keypoint's rounded location
/// (clipped at the border) in HSV. Chromatic (S >= grey_below): hue bin * saturation_levels +
/// saturation level; achromatic: hue_bins * saturation_levels + brightness level. Throws Error on
/// an empty image, a type other than 8-bit 1 or 3 channels, or a keypoint outside the image.
std::vector<std::int32_t> colour_words(const cv::Mat& image,
                                       const std::vector<cv::KeyPoint>& keypoints,
                                       const ColourWordOptions& options);

/// How many pixels of `mask` (8-bit, the image's size; nonzero: in) have each colour word
/// (0..options.count()-1): every pixel's patch mean as colour_words takes it, a dense colour
/// histogram of a region (a blob's own pixels, not only its features' points). Throws Error on an
/// empty image, a type other than 8-bit 1 or 3 channels, or a mask of another size or type.
std::vector<double> colour_word_counts(const cv::Mat& image, const cv::Mat& mask,
                                       const ColourWordOptions& options);

/// The word (0..options.count()-1) of one BGR colour, components 0-255 (what colour_words gives a
/// patch of that mean colour).
std::int32_t colour_word(const cv::Vec3b& bgr, const ColourWordOptions& options);

/// A document with colour words: `words` (each feature's vocabulary word, as bag_of_words gives
/// them) followed by each feature's colour word numbered after the vocabulary's words
/// (`vocabulary_size` + word), so that one corpus of vocabulary_size + ColourWordOptions::count()
/// words holds both; N features give 2N tokens. Throws Error when the two lists differ in length
/// or a colour word is negative.
std::vector<std::int32_t> with_colour_words(std::vector<std::int32_t> words,
                                            const std::vector<std::int32_t>& colours,
                                            int vocabulary_size);

/// The colour words' options when they are on, else none: what document_words and
/// document_vocabulary_size take (LearnOptions, SelfSupervisionOptions and RecognizeTrainOptions
/// hold a flag beside the grid).
inline std::optional<ColourWordOptions> colour_if(bool on, const ColourWordOptions& options) {
  return on ? std::optional(options) : std::nullopt;
}

/// The words a corpus of documents made with `colour` has: the vocabulary's, and with colour
/// words their count after them.
int document_vocabulary_size(const Vocabulary& vocabulary,
                             const std::optional<ColourWordOptions>& colour);

/// The document of features `f` of `image`: their vocabulary words (bag_of_words) and, with
/// `colour`, their colour words after them (with_colour_words; 2N tokens).
std::vector<std::int32_t> document_words(const Vocabulary& vocabulary, const cv::Mat& image,
                                         const Features& f,
                                         const std::optional<ColourWordOptions>& colour);

}  // namespace proprio::features

#pragma once
// Binary segmentation by a minimum s-t cut on the pixel grid (Boykov & Jolly 2001; max-flow by
// Boykov & Kolmogorov 2004, Boost.Graph's boykov_kolmogorov_max_flow). The thesis's "GraphCuts"
// (5.1.1): the Fitzpatrick & Metta baseline and M-L + graph cuts both use it.
//
// Energy of a labelling L (1 = object, 0 = background):
//   E(L) = sum_p D_p(L_p) + sum_{p,q neighbours, L_p != L_q} w_pq
//   w_pq = smoothness * exp(-beta |I_p - I_q|^2) / dist(p, q)     (Boykov-Jolly contrast term)
//   beta = 1 / (2 <|I_p - I_q|^2>) over the image's neighbour pairs, unless given.
// Hard seeds fix a pixel's label (its unary cost for the other label is larger than any cut
// through its neighbours, Boykov-Jolly's K).

#include <opencv2/core.hpp>
#include <string>

namespace proprio::segmentation {

struct GraphCutOptions {
  /// 4- or 8-connected grid (diagonal pairs weighted by 1/sqrt(2)).
  int connectivity = 8;
  /// Weight of the pairwise (Potts) term relative to the unary costs.
  double smoothness = 2.0;
  /// beta of the contrast term; <= 0: 1 / (2 mean |I_p - I_q|^2) of the image (Rother et al.).
  double contrast_beta = 0.0;
  /// The cut runs on a grid whose larger side is at most this many pixels (the image, unary
  /// costs and seeds are reduced with area averaging; the mask comes back at full size). Boost's
  /// BK on a full 640x480 8-connected grid takes about 0.4 s; at 320 about 0.1 s. 0: full size.
  int max_side = 320;
  /// Costs are rounded to integers at this many units per 1.0 of cost (Boost's BK with floating
  /// capacities can stall on residuals of rounding size).
  double cost_resolution = 1000.0;
  /// Throws Error naming the bad field.
  void validate() const;
};

/// Inputs of one cut, all of one size. Costs are >= 0 and finite; either cost image may be empty
/// (then 0 everywhere).
struct GraphCutProblem {
  cv::Mat image;              ///< CV_8UC3 (BGR) or CV_8UC1: the contrast term; empty = Potts only
  cv::Mat1f cost_object;      ///< D_p(object)
  cv::Mat1f cost_background;  ///< D_p(background)
  /// Hard seeds: 0 free, kSeedObject, kSeedBackground. Empty = none.
  cv::Mat1b seeds;
  /// The grid's size (of whichever input is given).
  [[nodiscard]] cv::Size size() const;
};

inline constexpr unsigned char kSeedFree = 0;
inline constexpr unsigned char kSeedObject = 1;
inline constexpr unsigned char kSeedBackground = 2;

struct GraphCutSummary {
  int width = 0, height = 0;    ///< size of the grid that was cut (after any reduction)
  bool reduced = false;         ///< the cut ran on a reduced grid
  long long nodes = 0;          ///< pixels (without the two terminals)
  long long edges = 0;          ///< directed edges, reverses included
  double flow = 0.0;            ///< max-flow value = minimum energy, in cost units
  double beta = 0.0;            ///< contrast beta used
  long long object_pixels = 0;  ///< object pixels of the returned (full-size) mask
  double seconds_build = 0.0;
  double seconds_flow = 0.0;
  std::string message;
  /// What a person reads: the message.
  [[nodiscard]] std::string brief() const { return message; }
};

struct GraphCutResult {
  cv::Mat1b mask;  ///< 255 object, 0 background, at the problem's size
  GraphCutSummary summary;
};

/// Minimum cut of `problem`. Throws Error when the inputs have different sizes or types, a cost
/// is negative or not finite, or the grid is empty.
GraphCutResult graph_cut(const GraphCutProblem& problem, const GraphCutOptions& options);

/// Unary costs from an object probability map p in [0, 1]: D(object) = -ln max(p, eps),
/// D(background) = -ln max(1 - p, eps). Throws Error on NaN or values outside [0, 1].
void unary_from_probability(const cv::Mat1f& probability, cv::Mat1f& cost_object,
                            cv::Mat1f& cost_background, double eps = 1e-3);

/// E(L) of `mask` (255/0 at the grid's size) for the problem exactly as graph_cut builds it
/// without reduction (same rounding): graph_cut's summary.flow equals the minimum of this over all
/// labellings that respect the seeds. For tests and diagnostics.
double cut_energy(const GraphCutProblem& problem, const GraphCutOptions& options,
                  const cv::Mat1b& mask);

/// M-L followed by graph cuts (the thesis's "ML+GraphCuts", 5.1.1): the M-L map at the scored
/// frame as unary, the frame's colour contrast as pairwise term. With m = map / max(map) and f the
/// mask fraction, D(object) = unary_weight * max(0, f - m) and D(background) = unary_weight *
/// max(0, m - f): with no pairwise term this is exactly M-L's mask (m >= f), so f stays the free
/// parameter of the P-R curve and the cut only moves boundaries to image edges and fills holes.
/// `image` is the frame (8-bit BGR or grey) of the map's size, else Error. A zero map gives an
/// empty mask.
struct MlGraphCutOptions {
  double mask_fraction = 0.75;
  double unary_weight = 8.0;
  GraphCutOptions graph_cut = {};
  void validate() const;  ///< throws Error naming the bad field
};
GraphCutResult ml_graph_cut(const cv::Mat& image, const cv::Mat1f& map,
                            const MlGraphCutOptions& options);

/// beta = 1 / (2 <|I_p - I_q|^2>) over the 4- or 8-neighbour pairs of `image` (0 when the image
/// is constant).
double contrast_beta(const cv::Mat& image, int connectivity);

}  // namespace proprio::segmentation

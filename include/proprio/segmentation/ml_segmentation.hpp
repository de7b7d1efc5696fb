#pragma once
// Motion-Likelihood segmentation of the object the arm pushes (thesis Ch 4, SPEC §3).
//
// Five steps (4.1): a tracked over-segmentation of the video, dense optical flow, the
// end-effector's image position per frame, a per-region likelihood that the region moves as the
// arm does, and a threshold. The map is a running average over frames of each tracked region's
// likelihood (eq 4.21), so evidence from any frame lands on the region wherever it is.
//
// Region tracking: per-frame superpixels (SEEDS, SLIC) carry no identity from one frame to the
// next, so each frame's labels are relabelled by majority overlap with the previous frame's
// labels warped along the flow (a superpixel whose overlap is too small starts a new track).
// This keeps the cost per frame constant (the thesis's 6-D mean shift over the whole video is
// not), and a region keeps its integrated evidence while it moves.
//
// Integration: a region's score is (mean likelihood over the post-touch evidence intervals) x
// (mean arm-removal term (1 - p) / kappa over the pre-touch intervals in which it moved; 1 if it
// never moved before the touch). Eq 4.21 averages both kinds of interval together; with a long
// approach that would leave every still background region a score of n_pre / n_all.

#include <Eigen/Core>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "proprio/core/fields.hpp"
#include "proprio/episode/episode.hpp"

namespace proprio::segmentation {

/// Motion model of a region (4.4): a 2-D translation (4.6-4.7) or a homography (4.9-4.11).
enum class MotionModel { kTranslation, kHomography };

/// Dense optical flow. DIS presets are OpenCV's DISOpticalFlow; kLucasKanadeGrid is pyramidal
/// Lucas-Kanade (Bouguet) on a 4-pixel grid, as in the thesis, interpolated to every pixel.
enum class FlowMethod { kDisUltrafast, kDisFast, kDisMedium, kFarneback, kLucasKanadeGrid };

/// Per-frame over-segmentation (tracked by warping, see above). kMeanShift is the thesis's front
/// end (pyrMeanShiftFiltering + flood fill), about 0.5 s a frame at 640x480.
enum class OverSegmentation { kSeeds, kSlic, kMeanShift };

inline constexpr core::ChoiceNames<MotionModel, 2> kMotionModelNames{
    {{"translation", MotionModel::kTranslation}, {"homography", MotionModel::kHomography}}};
inline constexpr core::ChoiceNames<FlowMethod, 5> kFlowMethodNames{
    {{"dis-ultrafast", FlowMethod::kDisUltrafast},
     {"dis-fast", FlowMethod::kDisFast},
     {"dis-medium", FlowMethod::kDisMedium},
     {"farneback", FlowMethod::kFarneback},
     {"lk", FlowMethod::kLucasKanadeGrid}}};
inline constexpr core::ChoiceNames<OverSegmentation, 3> kOverSegmentationNames{
    {{"seeds", OverSegmentation::kSeeds},
     {"slic", OverSegmentation::kSlic},
     {"meanshift", OverSegmentation::kMeanShift}}};

struct MlOptions {
  MotionModel model = MotionModel::kTranslation;
  FlowMethod flow = FlowMethod::kDisFast;
  OverSegmentation regions = OverSegmentation::kSeeds;
  /// Approximate number of superpixels per frame (SEEDS/SLIC).
  int region_count = 400;
  /// Sigma = lambda I of the error density, pixels^2 (4.4.2; 10-50 makes little difference).
  double lambda = 25.0;
  /// Mask = map >= mask_fraction * max(map) (5.1.1's optimum, 0.75).
  double mask_fraction = 0.75;
  /// The depth variant's (use_depth) mask fraction instead of mask_fraction; 0 = mask_fraction.
  /// With the outline cut at depth steps the background's map is near 0, while the pushed object
  /// turns and its parts far from the contact score lower than the part at it: a lower
  /// fraction takes them in (tuning recording, docs/results/segmentation-eval.md, session 12).
  double depth_mask_fraction = 0.5;
  /// The fraction this configuration's mask uses (depth_mask_fraction or mask_fraction).
  [[nodiscard]] double effective_mask_fraction() const {
    return use_depth && depth_mask_fraction > 0 ? depth_mask_fraction : mask_fraction;
  }
  /// The map is clipped at the value that this fraction of its pixels reach (its robust peak),
  /// so that a sliver brighter than the object does not set the mask's threshold. 0 = off.
  double peak_area = 0.01;
  /// Arm removal (eq 4.18): before the first touch the likelihood is (1 - p) / kappa.
  double kappa = 1.0;
  /// Robust mean (Algorithm 1): flat-kernel bandwidth c, pixels, and stopping tolerance, pixels.
  double robust_bandwidth = 2.0;
  double robust_tolerance = 0.01;
  int robust_max_iterations = 30;
  /// Homography RANSAC (Algorithm 2): reprojection threshold, pixels; minimum flow samples.
  /// 3 px, not 1: points carried through an interval (homography_over_interval) drift by a
  /// pixel or two (held objects: 0.39 -> 0.41 spirit level, 0.39 -> 0.45 bottle).
  double ransac_threshold = 3.0;
  int homography_min_points = 12;
  /// Homography model: fit each region's homography once per evidence interval, to its points
  /// carried along the flow from where it joined the interval, rather than multiply the frame
  /// pairs' fits (a pixel or two of motion each, which leaves a small region's perspective
  /// terms to the noise).
  bool homography_over_interval = true;
  /// Model selection within the homography model: a region whose interval fit makes fewer
  /// than this fraction of its points more inliers (within ransac_threshold) than its robust
  /// translation does is judged by its translation. 0 = always the homography; in [0, 1]. On
  /// the 30 held or turning episodes 0.25 beat both 0 and the translation model on each object
  /// (docs/results/segmentation-eval.md).
  double homography_selection = 0.25;
  /// Evidence intervals: the arm moves only a few pixels a frame, less than sqrt(lambda), so one
  /// frame pair barely tells a still region from one moving with the arm. Motion is therefore
  /// accumulated per track from the interval's first frame until the arm has moved
  /// evidence_step pixels in the image, and only then compared with the arm's displacement (one
  /// term of eq 4.21). Frames where the arm is still thus carry no evidence at all: a still region
  /// matching a still arm says nothing.
  double evidence_step = 12.0;
  /// The same before the first touch, where it serves arm removal (eq 4.18), pixels: the arm's
  /// approach is slow and its regions are short-lived, and a region that moves with the arm
  /// matches it over any span; still regions are not penalised (min_region_motion).
  double arm_removal_step = 6.0;
  /// Arm removal (eq 4.18) counts only tracks that moved at least this far, pixels, in a
  /// pre-touch interval: the arm is what moves like the arm before the touch; a still region
  /// is not made more probable by the arm moving elsewhere.
  double min_region_motion = 3.0;
  /// Arm removal (eq 4.18) averaged over every pre-touch interval in which the region was
  /// judged, an interval in which its flow moved less than min_region_motion counting as no arm
  /// evidence ((1 - p) / kappa taken as 1), rather than over only those in which it moved. The
  /// arm moves in every interval it is seen in; a piece of the still object that moved in one
  /// (a superpixel straddling its outline and the moving backdrop or the approaching arm) is not
  /// taken for the arm. Traced on the tuning recording: with arm removal off, M-L's recall on
  /// the bottles and mugs rose to 0.95-0.98 (docs/results/segmentation-eval.md, session 13).
  bool arm_removal_seen = true;
  /// Arm removal per pixel at the first touch (monocular M-L only; the depth variant's regions
  /// are cut at depth steps): the map is painted on the first-touch frame's regions, and a
  /// region there that straddles the still object and the arm beside it (a superpixel of the
  /// mug's side next to the gripper, traced on the tuning recording,
  /// docs/results/segmentation-eval.md, session 17) carries the arm's pre-touch record (eq
  /// 4.18) into the object's pixels. A pixel whose grey level changed by no more than 3 between
  /// any two frames since the arm was last pixel_still_span pixels from its
  /// touch position, and whose Sobel gradient |gx| + |gy| at the touch is at least
  /// pixel_still_gradient (so a motion of a pixel would have changed it), did not move before the
  /// touch: it is not the arm; and if, once the arm has moved evidence_step pixels past its touch
  /// position (by d, image pixels), the frame then matches the touch frame displaced by d
  /// better than undisplaced at that pixel (5x5 mean absolute differences, by pixel_motion_margin),
  /// it moved as the arm did after the touch: the pushed object, not the still background beside
  /// it. Such pixels (closed with a 5x5 disc, to take in the plain gaps between them) get their
  /// region's post-touch evidence alone (eq 4.21 without eq 4.18's term) when that is higher.
  /// Other pixels keep their region's value; a streamed map (stream_maps) of the touch frame,
  /// painted before the arm moved on, is unchanged. Off by default: on the tuning recording it
  /// raised all six mugs (0.782 -> 0.868) and the 24 episodes' mean (0.810 -> 0.833), but it
  /// lets some of a textured arm's pixels back in (the synthetic push: by chance unchanged from
  /// frame to frame, then moving with the arm), and on held-out episodes the bottles' and
  /// rabbits' precision fell (docs/results/segmentation-eval.md, session 17).
  bool pixel_arm_removal = false;
  double pixel_still_gradient = 24.0;
  double pixel_still_span = 6.0;
  double pixel_motion_margin = 2.0;
  /// Carried touch pixels (monocular and depth alike): the map is painted on the first-touch
  /// frame's regions, and a region there that straddles the object's outline (the bottle's
  /// neck and the wall behind it, the mug's side and the gripper) gives both sides one score.
  /// With this on, each pixel of the first-touch frame is carried forward along the flow (the
  /// backward flow inverted per frame, q + b(q) = p, from the pixel's last motion; a pixel for
  /// which no such q is found within 1 px was covered and is lost) while the arm moves
  /// carried_span pixels past its touch position; every carried_step pixels of that motion it
  /// notes the track it stands in, where its 5x5 mean grey level is still within carried_match
  /// of the touch frame's (else that sample says nothing: the flow carried a piece of the
  /// background along the object's edge). Where at least half the samples have it, the pixel
  /// takes the median of those tracks' scores (capped at the regions' peak, since the
  /// regions' scores are smoothed and the tracks' are not), or with carried_max the higher of
  /// that and its region's value. On by default since session 22, with carried_fb 0.25: without
  /// the forward-backward check recall rose everywhere but precision fell where the flow
  /// carried background pixels with the object (session 20: bottles and rabbits fell); with it,
  /// held-out (held2) 0.833 -> 0.874, every object up (docs/results/segmentation-eval.md).
  bool carried_pixels = true;
  double carried_span = 36.0;
  double carried_step = 6.0;
  bool carried_max = true;
  double carried_match = 12.0;
  /// Forward-backward check of the carried pixels, px (0 = off): in each frame pair of the
  /// carrying window the forward flow is computed as well, and a carried pixel whose forward
  /// flow from its position p does not land within this of the q the inverted backward flow
  /// gave (|p + f(p) - q|) is lost: the flow there is not consistent both ways, as on a rim
  /// of background dragged along the object's edge or a pixel being covered. Costs one more
  /// flow per frame while the arm moves carried_span pixels after the touch. 0.25 chosen on the
  /// tuning recording (1 and 0.5 px let the rabbit's background rim through).
  double carried_fb = 0.25;
  /// The depth variant (use_depth) carries pixels too only with this on: on held2 the depth
  /// variant's mean did not change with them (0.928 either way; mug 0.914 -> 0.902, rabbit
  /// 0.916 -> 0.932), so its default stays as it was (session 22).
  bool carried_with_depth = false;
  /// Colour check of the carried pixels, BGR distance (0 = off): a sample in which a carried
  /// pixel's first-touch colour lies farther than this from the mean colour of the track it
  /// stands in says nothing (a piece of the background carried onto the object, as the table
  /// at the mug's rim, which the forward-backward check lets through because the flow there is
  /// consistent both ways). Session 23; off by default (docs/results/segmentation-eval.md).
  double carried_colour = 0.0;
  /// The baseline's evidence at the touch (monocular only; 0 = off): the Fitzpatrick & Metta
  /// cut of the first-touch frame (segment_fm with its default options on frames t-2, t-1, t:
  /// the frame difference outside the arm's dilated motion, filled by a graph cut, the part
  /// nearest the end-effector) is computed while streaming, and a touch-frame region at least
  /// touch_fm_fraction of whose pixels lie in it scores at least touch_fm times the map's peak.
  /// For regions the motion likelihood lost (a static bottle's upper body, which the smoothing
  /// pulls down). The depth variant ignores it. On by default since session 23: on the tuning
  /// recording the bottles rose 0.771 -> 0.832 (static 0.67 -> 0.80), every other object within
  /// 0.001; held-out (held2) 0.874 -> 0.887, bottle 0.836 -> 0.897, mug 0.830 -> 0.831, the
  /// others unchanged (docs/results/segmentation-eval.md). Costs a colour frame copy per frame
  /// before the touch and one baseline cut at it.
  double touch_fm = 1.0;
  double touch_fm_fraction = 0.5;
  /// The baseline's touch cut as evidence against (monocular, with touch_fm > 0): where the cut
  /// and M-L's mask at the first touch agree (intersection over union at least touch_fm_agree; a
  /// baseline that found something else, as on the book, leaves the map alone), the map is set
  /// to 0 farther than touch_fm_margin pixels from both the cut and the baseline's arm model (the
  /// arm's dilated motion, where the cut says nothing). For the rim of table the regions and the
  /// carried pixels give the mug and the bottle (session 24). On by default, margin 1 px, since
  /// session 26: on the 24 tuning episodes mean Jaccard 0.843 -> 0.861 (bottle 0.832 -> 0.885,
  /// mug 0.829 -> 0.850), held out (held2) 0.887 -> 0.895 (bottle 0.897 -> 0.911, mug 0.831 ->
  /// 0.857), book, rabbit and spirit level unchanged (docs/results/segmentation-eval.md).
  bool touch_fm_against = true;
  double touch_fm_agree = 0.5;
  double touch_fm_margin = 1.0;
  /// The baseline's touch cut filled in, pixel by pixel (monocular, with touch_fm > 0; 0 = off):
  /// where the cut and M-L's mask at the first touch agree (touch_fm_agree, as above), every
  /// pixel of the cut outside the baseline's arm model scores at least touch_fm_fill x the map's
  /// peak. For the regions that straddle the object's outline: touch_fm raises a region only
  /// when touch_fm_fraction of it lies in the cut, so the object's part of a straddling region
  /// is lost (on the tuning bottles 95 % of M-L's missed pixels lie inside the cut). On by
  /// default since session 26: tuning mean of 24 0.861 -> 0.880 (bottle 0.885 -> 0.922, mug
  /// 0.850 -> 0.888), held out (held2) 0.895 -> 0.909 (bottle 0.911 -> 0.951, mug 0.857 ->
  /// 0.891), book, rabbit and spirit level unchanged (docs/results/segmentation-eval.md).
  double touch_fm_fill = 1.0;
  /// The mask's outline refined pixel by pixel at the first touch (monocular, where the
  /// baseline's cut and M-L's mask agree as above; 0 = off): within touch_fm_refine pixels of
  /// the outline, each pixel goes to the object or the background by OpenCV's GrabCut (colour
  /// mixtures of the mask's inside and the scene around it, contrast-weighted smoothness; Rother
  /// et al. 2004) run on the touch frame, with the mask's inside and the scene beyond the band
  /// held fixed. Pixels it gives the object score the map's peak, those it gives the background
  /// 0; the baseline's arm model is left as it was. For what the regions add along the outline:
  /// a straddling region's table pixels (on the held-out bottles, M-L's loss to the baseline is
  /// a 1 px rim of table). Deterministic: GrabCut's k-means starts from a fixed seed. 4 px by
  /// default since session 27: tuning mean of 24 0.880 -> 0.895 (bottle 0.922 -> 0.954, mug
  /// 0.888 -> 0.916), held out (held2) 0.909 -> 0.921 (bottle 0.951 -> 0.979, mug 0.891 ->
  /// 0.921), book, rabbit and spirit level unchanged (docs/results/segmentation-eval.md).
  double touch_fm_refine = 4.0;
  /// The refinement also settles the mask's pixels inside the baseline's arm model (with
  /// touch_fm_refine > 0): there the cut says nothing, and the regions beside the arm that move
  /// with it after the touch are the arm's rim (its edge and shade the arm model's dilation
  /// does not cover; on the fresh held-out bottles, M-L's loss to the baseline: precision 0.91
  /// against 0.96, recall 1.00). Those pixels go to GrabCut as probably the object's, whatever
  /// their distance to the outline, and take its answer; the arm model's pixels outside the
  /// mask stay as they were. On by default since session 28: tuning mean of 24 0.895 -> 0.905
  /// (bottle 0.954 -> 0.991, mug 0.916 -> 0.918, book and rabbit unchanged), held out (held2)
  /// 0.921 -> 0.924 (bottle 0.979 -> 0.994) (docs/results/segmentation-eval.md).
  bool touch_fm_refine_arm = true;
  /// Integration (eq 4.21): a region's mean likelihood over the post-touch intervals it was
  /// seen in, but over at least this fraction of all of them (the unseen count as 0): one lucky
  /// interval must not match a region followed through the whole push. Off (0) by default:
  /// regions that the over-segmentation cuts short lost more than lucky ones gained.
  double min_evidence_fraction = 0.0;
  /// Texture: dense flow in a texture-less area (a plain table, the arm's plain links) is filled
  /// in from the neighbours and says nothing of the region's own motion. Only pixels whose
  /// Sobel gradient |gx| + |gy| (grey levels, 3x3 kernel) is at least min_gradient feed a
  /// region's motion; a region with fewer than min_textured_samples of them (every 2nd pixel
  /// each way) gives no evidence in that interval. Off (0) by default: on the simulated scenes
  /// it cost more object regions than it saved.
  double min_gradient = 0.0;
  int min_textured_samples = 6;
  /// Photometric support, grey levels: a region's motion over an evidence interval counts only
  /// when its pixels match the previous frame displaced by the motion (its robust mean over each
  /// frame pair, also under the homography model) better than undisplaced by at least this much
  /// on average per pixel and frame; otherwise the region is taken to be still. Dense flow fills
  /// a plain area next to the pushed object (the table ahead of it) with the object's motion;
  /// the image there fits both equally. Frame pairs where most of the image changed (the light
  /// moved) are left out. 0 = off.
  double min_photometric_gain = 3.0;
  /// Relative photometric check (photometric_relative > 0): the least gain is this fraction of
  /// the gain the region's own contrast predicts for its motion m, mean |I_t-1(x) - I_t-1(x - m)|
  /// over its pixels (grey levels; the gain a region that did move by m shows, since then
  /// I_t(x) = I_t-1(x - m); a still one shows its negative), when that is lower than
  /// min_photometric_gain, which stays the cap and the switch (0 = no check at all). A region
  /// of dark, low-contrast texture moving 2-3 px a frame (the simulated bottle) gains less
  /// than 3 grey levels over "still" and fails the absolute floor, though the image supports
  /// its motion as well as it can; a plain area (the table ahead of the pushed object) predicts
  /// a gain near 0, and is held by min_photometric_contrast. 0 = off: the absolute floor alone.
  /// Off by default: on the tuning recording 0.15 changed only three static bottles (two up,
  /// one down; mean of 18 episodes 0.765 -> 0.768), within the per-episode noise
  /// (docs/results/segmentation-eval.md, session 15).
  double photometric_relative = 0.0;
  /// ... and the relative floor applies only where at least half the region's pixels (the
  /// median) predict a gain of at least this, grey levels a pixel a frame: a plainer region's
  /// gain is not told from the 8-bit rounding, and a region straddling a plain table and the
  /// pushed object's edge has the edge's gain and prediction alike (its mean ratio near 1);
  /// both are left to min_photometric_gain.
  double min_photometric_contrast = 0.5;
  /// The same check before the touch: an unsupported motion does not make a region arm. Off
  /// (false), the tuning recording's mean rose 0.810 -> 0.827 (pieces of the arm beside the
  /// static bottles and two rabbits removed; the mugs unchanged) and the held-out one's fell
  /// 0.833 -> 0.828 (a bottle's recall), so it stays on (docs/results/segmentation-eval.md,
  /// session 19).
  bool photometric_pre_touch = true;
  /// A region track that the over-segmentation ends hands its evidence on to the track that
  /// took most of its pixels only when their last motions, as the image supports them
  /// (min_photometric_gain), differ by at most this, pixels a frame: a still region covered by
  /// the pushed object must not inherit the object's evidence. With the photometric check a
  /// bled flow no longer passes for motion, and 3 px kept the pieces of fragmenting objects
  /// (the bottle: 0.45 -> 0.71 static) where 0.75 px lost them.
  double handover_motion = 3.0;
  /// ... and only while their mean post-touch likelihoods (when both have some) differ by at
  /// most this: the pushed object slides over the still table ahead of it at a pixel or two a
  /// frame, within handover_motion, and the table's pieces it covers hand over to the object's
  /// track; their own intervals said "still". 1 = off. Between 0.4 and 0.7 the Chapter 5
  /// dataset scores alike (0.79 static, 0.67 moving; 0.73 / 0.66 with it off).
  double handover_evidence = 0.5;
  /// Camera motion (a shaking or drifting mount): the arm's image track is projected through the
  /// calibrated, still camera, but a moving camera adds its own motion to every pixel. At the
  /// close of each evidence interval the current frame is registered to the interval's first
  /// (estimate_global_motion on the flow between them), and each region's position is taken
  /// back into that first frame's camera before it is compared with the arm's displacement.
  /// Intervals whose camera motion at the image centre is below min_camera_motion, pixels, are
  /// left as they are (a still camera: the fit's noise). Costs one flow per interval.
  bool compensate_camera_motion = true;
  double min_camera_motion = 0.25;
  /// Region smoothing (smooth_region_scores, region_smoothing.hpp): the painted frame's region
  /// scores are smoothed over the regions' adjacency, each held by its evidence
  /// (smoothing_weight x its post-touch intervals x its boundary length) and pulled towards its
  /// neighbours in proportion to their common boundary and exp(-|dc|^2 / (2 sigma^2)) of their
  /// mean BGR colours. Regions that no evidence reached (a piece of the object that the
  /// over-segmentation re-cut at the touch, handed over to no track because a shaking camera gave
  /// the two pieces' frame pairs different motions) take their colour-alike neighbours' scores,
  /// and a piece with one unlucky interval yields to the object around it. Measured on the
  /// Chapter 5 dataset in docs/results/segmentation-eval.md.
  bool region_smoothing = true;
  double smoothing_weight = 0.01;
  double smoothing_colour_sigma = 25.0;
  /// Evidenced regions keep their own score (0 = off): after the smoothing, a region with at
  /// least this many post-touch intervals of its own takes the higher of its smoothed score and
  /// its own, the latter capped at the smoothed scores' robust peak (the score that peak_area of
  /// the frame's pixels reach after the smoothing), so a well-evidenced piece of a dark object
  /// is not pulled down by like-coloured background beside it, and a high sliver cannot raise
  /// the peak that sets the mask's threshold. Regions with less evidence are smoothed as usual.
  int smoothing_keep_evidence = 0;
  /// Processing scale: over-segmentation, flow and tracking run on images resized by this factor
  /// (speed); the map is returned at full size.
  double scale = 1.0;
  /// SEEDS iterations / SLIC iterations per frame.
  int region_iterations = 2;
  /// Push-direction prior (4.6, a position prior from proprioception): when the arm's path after
  /// the touch is straight, the map is multiplied by 1 ahead of the pusher's tip, falling to 0
  /// over direction_ramp pixels behind it (where the arm is). Off for curved paths (objects
  /// carried in 3D), where "ahead" means nothing.
  bool direction_prior = true;
  double direction_ramp = 8.0;
  /// Contact prior (4.6, from proprioception): the pushed object touches the end effector. The
  /// map's bright blobs (map >= mask_fraction x its maximum, joined across gaps of up to
  /// contact_gap pixels) that come no nearer than contact_radius pixels to the end effector's
  /// image position in the painted frame are set to 0: a patch of the background that moved
  /// with the arm somewhere else in the image is not the object the arm touches. When no blob
  /// comes that near, the map is left as it is. Full-size pixels.
  bool contact_prior = true;
  double contact_radius = 20.0;
  double contact_gap = 10.0;
  /// Depth variant (thesis 9.2, "a rigid 3D motion model from stereo or depth"; `segment
  /// --method ml-depth`): every frame comes with a depth image (MlSegmenter::DepthFrame). Each
  /// region's flow samples are back-projected through the intrinsics at their depths in the two
  /// frames, and the region's 3-D translation over the evidence interval (robust mean of the
  /// samples' 3-D motions, per frame pair) is compared with the arm's 3-D displacement in the
  /// camera frame: p = exp(-|e|^2 / (2 depth_lambda)), e in mm. A region with fewer than
  /// min_depth_samples samples of known depth in a frame pair of its interval is judged by the
  /// 2-D model in that interval. Superpixels are also cut at depth steps (split_at_depth_steps):
  /// the object's outline against the table behind it is a depth discontinuity that colour may
  /// not show. Depth holes (0, NaN, infinite) are unknown: their samples are left out, they cut
  /// nothing. Camera motion is not compensated in 3-D.
  bool use_depth = false;
  /// Sigma = (depth_lambda + depth_relative |d3|^2) I of the 3-D error density, mm^2, where d3
  /// is the arm's 3-D displacement over the region's span in the interval: a fixed noise floor
  /// plus a part that grows with the arm's motion, so that a still region scores about
  /// exp(-1 / (2 depth_relative)) however far the arm moved (the 2-D model's lambda = 25 px^2
  /// with evidence_step 12 px gives a still region exp(-144 / 50) = 0.06, as depth_relative
  /// 0.17 does). depth_relative 0: the fixed depth_lambda alone.
  double depth_lambda = 400.0;
  double depth_relative = 0.0;
  /// Depth variant: the 3-D likelihood multiplies the 2-D one (both models must agree) rather
  /// than replacing it; where the 3-D likelihood is flat, the 2-D one still orders the regions
  /// (docs/results/segmentation-eval.md, session 11: held-out ml-depth 0.588 -> 0.804).
  bool depth_with_2d = true;
  /// Robust 3-D mean bandwidth, mm.
  double depth_bandwidth = 10.0;
  /// Depth step between neighbouring pixels that cuts a superpixel, mm; 0 = no cut. 10 rather
  /// than 20 on the tuning recording (docs/results/segmentation-eval.md, session 14): a mug's
  /// handle stands only a centimetre or two above the table seen through it, and the bottle's
  /// and mug's outlines against the table behind them at the foot are shallow steps too.
  double depth_edge = 10.0;
  /// Depth variant: the region smoothing (region_smoothing) does not join two regions across
  /// their boundary's pixel pairs with a depth step above depth_edge: the object's pieces cut
  /// at its outline keep their own evidence instead of taking the background's behind them.
  bool depth_smoothing = true;
  int min_depth_samples = 6;
  /// Depth variant: the table cut. The pushed object stands on the table, so a pixel whose
  /// depth puts it less than table_clearance mm above the table plane is not the object: its
  /// map value is set to 0 (before the priors and the threshold). The plane is the depth's
  /// dominant height along the world's up direction (table_heights; DepthFrame::up, from the
  /// calibration). Traced on the tuning recording (docs/results/segmentation-eval.md, session
  /// 16): ml-depth's false positives on the mugs and rabbits were table pixels (the table
  /// through the handle, the strip around the rabbit's outline), within 2 mm of the plane, and
  /// 2 mm raised all 24 tuning episodes (static 0.888 -> 0.936, moving 0.845 -> 0.924). The
  /// object's own contact band (its pixels within table_clearance of the table, about 1% of
  /// it) is lost with them. 0 = off; pixels of unknown depth and frames without an up
  /// direction or a table are never cut. An object thinner than the clearance is cut whole.
  double table_clearance = 2.0;
  /// Optional prior map (4.6), CV_32F in [0, 1] of the frames' size; multiplied into the map.
  cv::Mat1f prior;
  /// Keep the map painted with every frame's regions (MlResult::frame_maps).
  bool keep_frame_maps = false;
  /// MlSegmenter::push paints the current map (FrameOutput::map: scores, smoothing, priors;
  /// outside the stage timers; callgrind: 11 M instructions a frame at 320x240, 7% of push; all 0
  /// and not painted before the first touch). segment_ml turns it off: it paints only the frames
  /// it returns, once the whole episode has been seen.
  bool stream_maps = true;
  /// MlSegmenter keeps every frame's track labels (for map_for_frame; 4 bytes a processed pixel
  /// a frame). When false it keeps only the first-touch frame's.
  bool keep_frame_labels = true;
  /// Throws Error naming the bad field.
  void validate() const;

  /// The options a tuning run may set, by name (the tuning tool reads "key=value" with these
  /// names). Bounds are validate()'s (given here only where a command binds the field).
  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v.choice(self.model, {"model", "Motion model of the regions (4.3)"}, kMotionModelNames);
    v.choice(self.flow, {"flow", "Dense optical flow"}, kFlowMethodNames);
    v.choice(self.regions, {"regions", "Per-frame over-segmentation"}, kOverSegmentationNames);
    v(self.region_count, {"region_count", "Superpixels per frame (SEEDS/SLIC)"});
    v(self.region_iterations, {"region_iterations", "Over-segmentation iterations"});
    v(self.lambda, {"lambda", "Sigma = lambda I of the error density, px^2 (4.4.2)"});
    // Flags of `segment` and `evaluate segmentation`: --fraction, --depth-fraction.
    v(self.mask_fraction, {"mask_fraction",
                           "M-L mask = map >= fraction * max (thesis 5.1.1: 0.75); also "
                           "ml-sparse's and ml-graphcut's",
                           core::positive_at_most(1.0), nullptr, "fraction"});
    v(self.depth_mask_fraction,
      {"depth_mask_fraction",
       "ml-depth's mask = map >= depth-fraction * max (0 = --fraction's; tuned on the tuning "
       "recording, docs/results/segmentation-eval.md)",
       core::between(0.0, 1.0), nullptr, "depth_fraction"});
    v(self.peak_area, {"peak_area", "Fraction of the frame that defines the map's peak"});
    v(self.kappa, {"kappa", "Prior ratio of the object and background hypotheses"});
    v(self.robust_bandwidth, {"robust_bandwidth", "Robust motion fit bandwidth, px"});
    v(self.ransac_threshold, {"ransac_threshold", "Homography RANSAC threshold, px"});
    v(self.homography_over_interval,
      {"homography_over_interval", "Fit homographies over the evidence interval"});
    v(self.homography_selection, {"homography_selection", "Evidence margin that selects it"});
    v(self.arm_removal_seen, {"arm_removal_seen", "Arm removal over every interval seen"});
    v(self.pixel_arm_removal, {"pixel_arm_removal", "Arm removal per still pixel at touch"});
    v(self.pixel_still_gradient,
      {"pixel_still_gradient", "Least Sobel gradient of a still pixel, grey levels"});
    v(self.pixel_motion_margin, {"pixel_motion_margin", "Least gain of a moved pixel, grey"});
    v(self.pixel_still_span, {"pixel_still_span", "Arm motion a still pixel stood through, px"});
    v(self.carried_pixels,
      {"carried_pixels", "Touch pixels take the tracks they are carried into"});
    v(self.carried_span, {"carried_span", "Arm motion after the touch they are carried over, px"});
    v(self.carried_step, {"carried_step", "Arm motion between their samples, px"});
    v(self.carried_max, {"carried_max", "Higher of the carried median and the region's"});
    v(self.carried_match, {"carried_match", "Largest grey-level change of a carried pixel"});
    v(self.carried_fb, {"carried_fb", "Forward-backward flow check of carried pixels, px"});
    v(self.carried_with_depth, {"carried_with_depth", "The depth variant carries pixels too"});
    v(self.touch_fm, {"touch_fm", "Score of regions in the baseline's touch cut, x peak"});
    v(self.touch_fm_fraction, {"touch_fm_fraction", "Share of a region in that cut to count"});
    v(self.touch_fm_against,
      {"touch_fm_against", "Map set to 0 away from the baseline's cut where the two agree"});
    v(self.touch_fm_agree, {"touch_fm_agree", "Their least intersection over union to do so"});
    v(self.touch_fm_margin, {"touch_fm_margin", "Distance from the cut kept, px"});
    v(self.touch_fm_fill, {"touch_fm_fill", "Cut's pixels scored at least this x peak"});
    v(self.touch_fm_refine, {"touch_fm_refine", "Outline band refined by GrabCut, px (0 = off)"});
    v(self.touch_fm_refine_arm,
      {"touch_fm_refine_arm", "GrabCut also settles the mask's pixels in the arm model"});
    v(self.carried_colour,
      {"carried_colour", "Largest colour distance of a carried pixel to its track"});
    v(self.evidence_step, {"evidence_step", "Arm motion between evidence frames, px"});
    v(self.arm_removal_step, {"arm_removal_step", "Arm motion that removes its regions, px"});
    v(self.min_region_motion, {"min_region_motion", "Least region motion that counts, px"});
    v(self.min_evidence_fraction, {"min_evidence_fraction", "Least evidenced fraction"});
    v(self.min_gradient, {"min_gradient", "Least image gradient of a flow sample"});
    v(self.min_photometric_gain, {"min_photometric_gain", "Photometric check's least gain"});
    v(self.photometric_relative,
      {"photometric_relative", "Relative photometric check: least gain per predicted gain"});
    v(self.min_photometric_contrast,
      {"min_photometric_contrast", "Least predicted gain of the relative check, grey levels"});
    v(self.photometric_pre_touch, {"photometric_pre_touch", "Photometric check before touch"});
    v(self.handover_motion, {"handover_motion", "Largest hand-over motion difference, px"});
    v(self.handover_evidence, {"handover_evidence", "Evidence carried over a hand-over"});
    v(self.compensate_camera_motion, {"compensate_camera_motion", "Remove camera motion"});
    v(self.min_camera_motion, {"min_camera_motion", "Least camera motion compensated, px"});
    v(self.region_smoothing, {"region_smoothing", "Smooth region scores over the graph"});
    v(self.smoothing_weight, {"smoothing_weight", "Data weight of the smoothing"});
    v(self.smoothing_colour_sigma, {"smoothing_colour_sigma", "Colour sigma of the smoothing"});
    v(self.smoothing_keep_evidence,
      {"smoothing_keep_evidence", "Intervals a region needs to keep its own score"});
    v(self.scale, {"scale", "Image scale of the processing"});
    v(self.direction_prior, {"direction_prior", "Prior on the push direction"});
    v(self.contact_prior, {"contact_prior", "Keep blobs near the arm's contact"});
    v(self.contact_radius, {"contact_radius", "Contact prior radius, px"});
    v(self.contact_gap, {"contact_gap", "Contact prior gap, px"});
    v(self.use_depth, {"use_depth", "Depth variant: 3-D region motion (thesis 9.2)"});
    v(self.depth_lambda, {"depth_lambda", "Sigma = lambda I of the 3-D error, mm^2"});
    v(self.depth_relative, {"depth_relative", "3-D error sigma's part per arm motion^2"});
    v(self.depth_with_2d, {"depth_with_2d", "3-D likelihood times the 2-D one"});
    v(self.depth_bandwidth, {"depth_bandwidth", "Robust 3-D mean bandwidth, mm"});
    v(self.depth_edge, {"depth_edge", "Depth step that cuts a region, mm (0 = none)"});
    v(self.depth_smoothing, {"depth_smoothing", "No smoothing across depth steps"});
    v(self.min_depth_samples, {"min_depth_samples", "Least depth samples of a 3-D motion"});
    v(self.table_clearance, {"table_clearance", "Least height above the table, mm (0 = off)"});
  }
};

/// What happened (Ceres style).
struct MlSummary {
  int frames = 0;              ///< frames read
  int scored_frame = -1;       ///< frame the map was painted on (first touch); -1 never touched
  bool touched = false;        ///< the arm touched something
  int evidence_intervals = 0;  ///< evidence intervals closed (arm moved evidence_step)
  int tracks = 0;              ///< region tracks created over the episode
  /// Region tracks held at the end: the live ones and the ended ones whose evidence the first
  /// touch's map still needs (all of them with keep_frame_labels).
  int tracks_kept = 0;
  int camera_fits = 0;      ///< evidence intervals whose camera motion was found
  int camera_failures = 0;  ///< evidence intervals with no camera motion fit (not compensated)
  double mean_camera_motion = 0.0;  ///< mean camera motion over an interval, image centre, pixels
  std::string message;              ///< one line: what happened
  /// What a person reads: the message.
  [[nodiscard]] std::string brief() const { return message; }
  double mean_ms_regions = 0.0;  ///< over-segmentation + tracking, per frame
  double mean_ms_flow = 0.0;     ///< optical flow, per frame
  double mean_ms_model = 0.0;    ///< motion model + likelihood + integration, per frame
  double mean_ms_total = 0.0;    ///< all of it (disk I/O excluded), per frame
};

struct MlResult {
  std::optional<int> first_touch_frame;
  int scored_frame = -1;  ///< -1 = never touched ("no touch": map and mask empty)
  /// Probability map at the scored frame, in [0, 1], integrated over the WHOLE episode (regions
  /// are tracked, so later evidence counts).
  cv::Mat1f map;
  /// map >= mask_fraction * max(map) (all zero when the map is zero).
  cv::Mat1b mask;
  /// When keep_frame_maps: the integrated map painted with each frame's tracked regions.
  std::vector<cv::Mat1f> frame_maps;
  MlSummary summary;
};

/// Segments the pushed object of `episode` (needs frames, arm data; every frame of the camera's
/// size). Throws Error on an episode without frames or arm samples, or frames of different sizes.
/// An episode that never touches returns scored_frame = -1 and a "no touch" message. With
/// use_depth the episode must have depth images (Error naming the episode otherwise); the arm's
/// 3-D position is the arm sample's end effector taken into the camera frame by the calibration.
MlResult segment_ml(const episode::Episode& episode, const MlOptions& options);

/// The sparse variant (Algorithm 3, 4.5).
struct SparseOptions {
  /// Sigma = lambda I, pixels^2.
  double lambda = 25.0;
  /// Mean-shift bandwidth on feature velocities, pixels/frame.
  double velocity_bandwidth = 2.0;
  /// Keep clusters whose likelihood is >= tau.
  double tau = 0.5;
  /// Density: Gaussian blur sigma, pixels.
  double density_sigma = 12.0;
  double mask_fraction = 0.75;
  double kappa = 1.0;
  /// Arm image displacement, pixels, between the two frames of each matched pair.
  double evidence_step = 12.0;
  /// Lowe ratio test for SIFT matches.
  double ratio = 0.75;
  int max_features = 1500;
  void validate() const;

  template <class Self, class Visitor>
  static void describe(Self& self, Visitor& v) {
    v(self.lambda, {"lambda", "Sigma = lambda I, px^2"});
    v(self.velocity_bandwidth, {"velocity_bandwidth", "Mean-shift bandwidth, px/frame"});
    v(self.tau, {"tau", "Least likelihood of a kept cluster"});
    v(self.density_sigma, {"density_sigma", "Density blur sigma, px"});
    v(self.mask_fraction, {"mask_fraction", "Mask = map >= fraction x max"});
    v(self.kappa, {"kappa", "Prior ratio of the hypotheses"});
    v(self.evidence_step, {"evidence_step", "Arm motion between matched frames, px"});
    v(self.ratio, {"ratio", "Lowe ratio test"});
    v(self.max_features, {"max_features", "SIFT features per frame at most"});
  }
};

MlResult segment_ml_sparse(const episode::Episode& episode, const SparseOptions& options);

/// Streaming M-L (eq 4.21 is a running average): frames go in one at a time.
class MlSegmenter {
 public:
  struct FrameOutput {
    int frame = -1;
    /// Current integrated map painted with this frame's regions, [0, 1] (empty when
    /// MlOptions::stream_maps is off).
    cv::Mat1f map;
    double ms_regions = 0.0, ms_flow = 0.0, ms_model = 0.0, ms_total = 0.0;
  };

  /// A frame's depth (MlOptions::use_depth).
  struct DepthFrame {
    /// Depth along the optical axis, millimetres, of the frame's size: CV_16UC1 (0 = unknown)
    /// or CV_32FC1 (0, NaN or infinite = unknown). Anything else is an Error.
    cv::Mat depth;
    /// The end effector in the camera frame, millimetres (none if unknown: the frame's 3-D
    /// evidence falls back to 2-D).
    std::optional<Eigen::Vector3d> ee_camera;
    /// Camera intrinsics K, pixels of the full-size frame.
    Eigen::Matrix3d intrinsics = Eigen::Matrix3d::Identity();
    /// The world's up direction (normal of the level table) in the camera frame, unit (none:
    /// no table cut, MlOptions::table_clearance). segment_ml: the calibration's R times the
    /// world's +z.
    std::optional<Eigen::Vector3d> up;
  };

  /// Throws Error when options are invalid or the size is empty.
  MlSegmenter(const MlOptions& options, cv::Size image_size);
  ~MlSegmenter();
  MlSegmenter(MlSegmenter&&) noexcept;
  MlSegmenter& operator=(MlSegmenter&&) noexcept;

  /// One frame: 8-bit BGR image of image_size (else Error), the end-effector's image position,
  /// pixels (none if unknown: the frame pair carries no evidence), and whether the arm touched
  /// something since the previous frame (the first set flag ends arm removal, eq 4.18).
  /// With use_depth, `depth` must be given (Error naming the frame otherwise, or when its image
  /// is empty, of another size or type); without, it is ignored.
  FrameOutput push(const cv::Mat& bgr, std::optional<Eigen::Vector2d> ee_image, bool touching,
                   const DepthFrame* depth = nullptr);

  /// Frames pushed so far.
  [[nodiscard]] int frames() const;
  /// The first frame with touching set, if any.
  [[nodiscard]] std::optional<int> first_touch_frame() const;
  /// Integrated map painted with frame i's tracked regions (0 <= i < frames()).
  [[nodiscard]] cv::Mat1f map_for_frame(int i) const;
  /// Statistics so far (timings are means per frame).
  [[nodiscard]] MlSummary summary() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Height of each pixel above the table, mm (MlOptions::table_clearance): `depth` (CV_32F,
/// millimetres along the optical axis, 0 = unknown) back-projected through `k_inv` (inverse
/// intrinsics of the full-size frame; pixel (x, y) of depth is (x, y) * pixel_scale full-size
/// pixels), each point X (camera frame, mm) at height h = up . X along `up` (unit, camera
/// frame), less the table's height: the mode of h over the known pixels (1 mm bins, refined to
/// the mean of the heights within 2 mm of the modal bin), when at least min_table_share of
/// them lie within 2 mm of it (heights beyond +-32.768 m count as known, never as the table).
/// Unknown pixels, and every pixel when no table is found, get
/// +infinity (never below a clearance). Requires a finite unit `up`, pixel_scale > 0.
cv::Mat1f table_heights(const cv::Mat1f& depth, const Eigen::Matrix3d& k_inv,
                        const Eigen::Vector3d& up, double pixel_scale,
                        double min_table_share = 0.1);

/// Binary mask (255/0) of map >= fraction * max(map); all zero when the map's max is 0.
cv::Mat1b threshold_map(const cv::Mat1f& map, double fraction);

/// The contact prior (4.6, MlOptions::contact_prior), in place: the blobs of map >= fraction x
/// max(map), joined across gaps of up to `gap` pixels (a dilation by an ellipse of diameter
/// gap + 1), that have no pixel within `radius` pixels of `ee` (the end effector's image
/// position, pixels) are set to 0. Returns the number of blobs zeroed; leaves the map as it is
/// (returns 0) when no blob comes that near. Requires radius > 0, gap >= 0.
int apply_contact_prior(cv::Mat1f& map, const Eigen::Vector2d& ee, double fraction, double radius,
                        double gap);

}  // namespace proprio::segmentation

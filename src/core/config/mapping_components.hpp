#pragma once
// The mapping components' settings, declared once: each default is written here and each
// field's unit, range and doc string in MappingSettings::visit (mapping_settings.hpp), which
// binds them to the robot file's flat `mapping:` keys. The mapping library uses them as they
// are (mapping::AdamSettings is AdamSettings, ...). Fields the robot file does not set carry
// their doc here.

namespace vigs::config {

/// mapping::LossSettings: (1 - lambda_ssim) L1 + lambda_ssim (1 - SSIM) + lambda_depth L1(depth).
struct LossSettings {
  double lambda_ssim = 0.2;
  double lambda_depth = 0.1;
};

/// mapping::AdamSettings: one learning rate per parameter group. GS-ICP SLAM's, but for the
/// means: its 4e-6 m left them where insertion put them, and with the few iterations a live
/// keyframe gets, 2e-4 gives held-out views +0.4 dB and +0.008 SSIM (BENCHMARKS.md, the
/// twenty-fourth session; 4e-4 is as good, 1.6e-3 falls back).
struct AdamSettings {
  double lr_mean = 2e-4;
  double lr_log_scale = 5e-3;
  double lr_quat = 1e-3;
  double lr_opacity = 0.05;
  double lr_color = 2.5e-3;
  double beta1 = 0.9;    ///< not in the robot file
  double beta2 = 0.999;  ///< not in the robot file
  double eps = 1e-15;    ///< as 3DGS; not in the robot file
  /// Step only the Gaussians the iteration's view sees (Adam::step_selected); false: every
  /// Gaussian, as torch.optim.Adam.
  bool visible_only = true;
};

/// mapping::PruneSettings: Gaussians below min_opacity or with a standard deviation above
/// max_scale_m are pruned.
struct PruneSettings {
  double min_opacity = 0.005;
  double max_scale_m = 0.5;
};

/// mapping::InsertSettings (mapping/insertion.hpp says the rules).
struct InsertSettings {
  double voxel_m = 0.02;
  double opacity = 0.9;  ///< at full depth confidence (the flat opacity of the GS-ICP rule)
  double min_scale_m = 1e-4;
  double cover = 0.7;  ///< in-plane standard deviation per footprint width; not in the robot file
  double thin = 0.2;   ///< largest normal standard deviation per footprint width; likewise
};

/// mapping::FarFieldSettings (mapping/far_field.hpp says the rule): sparse far Gaussians where
/// the frame has no depth and the map renders nothing yet.
struct FarFieldSettings {
  double depth_m = 15.0;  ///< camera depth of the far Gaussians; 0 = no far field
  int stride_px = 8;      ///< one far Gaussian per stride x stride pixel block at most
  /// Far Gaussians keep the mean, scale and rotation insertion gave them; training changes
  /// only their colour and opacity. Their depth is a stand-in for "beyond the range", so
  /// nothing can fit their geometry: moved and reshaped, they turned into dark streaks at the
  /// corridor's end (people walking there, other views' parallax). BENCHMARKS.md, the
  /// twenty-fifth session.
  bool fixed_geometry = true;
};

/// mapping::SeeThroughSettings (mapping/see_through.hpp says the rule): Gaussians that later
/// keyframes see through (a surface measured well behind them) are pruned.
struct SeeThroughSettings {
  bool enabled = true;
  double margin_m = 0.1;       ///< in front of the measured surface by more than this...
  double margin_per_m = 0.03;  ///< ...plus this per metre of the Gaussian's depth
  int min_count = 2;           ///< keyframes that must see through a Gaussian to prune it
  double min_fraction = 0.5;   ///< and at least this share of the keyframes that vote on it
  bool missing_far = true;     ///< a pixel without depth is beyond the range (far), not unknown
  /// Only keyframes at most this many after the one that inserted a Gaussian vote on it
  /// (0 = every later keyframe).
  int max_age_keyframes = 30;
};

/// mapping::CloserRefineSettings (mapping/closer_refine.hpp says the rule): Gaussians that a
/// keyframe sees on its measured surface from much closer than their size stands for are
/// replaced by the keyframe's finer samples.
struct CloserRefineSettings {
  double ratio = 2.0;       ///< replaced when larger than ratio x the keyframe's sample; 0 = off
  double depth_rel = 0.05;  ///< on the measured surface: |d - z| <= this x d; not in the file
};

/// Pixels of the points the tracker flagged moving (pipeline/moving_pixels.hpp): masked out of
/// the keyframe's training view (depth -1: neither colour nor depth is a target).
struct MovingMaskSettings {
  bool enabled = true;
  int dilation_px = 2;  ///< added around each point's pixel-stride block
};

}  // namespace vigs::config

// From measured samples to a material: the ratios of each set (mean and standard deviation, as the
// error bars of Shrink & Morph Fig. 8), the sets ranked by contraction, the material file of the
// chosen set, the thickness curve of a thickness-ramp print (SCF 2020 §6: a monotone polynomial of
// degree at most 4), the speed curve of a speed-ramp print (Thermorph Fig. 6, the same kind of
// polynomial in the print speed), and the Fig.-8-like plots. Lengths in mm, curvatures in 1/mm,
// speeds in mm/s.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "calibration/measurements.h"
#include "material/material.h"
#include "material/speed_curve.h"
#include "material/thickness_curve.h"

namespace flatmorph {

struct MeanStd {
  double mean = 0;
  double std = 0;  // sample standard deviation (n - 1); 0 for one sample
};

struct SetFit {
  int set = 0;
  double nozzle_temperature = 0;  // degrees C
  double layer_height = 0;        // mm
  int layers = 0;
  double thickness = 0;         // mm, the mean printed thickness of the samples
  int samples = 0;              // measured (skipped ones left out)
  bool thickness_ramp = false;  // from a thickness-ramp sheet
  bool speed_ramp = false;      // from a speed-ramp sheet
  double print_speed = 0;       // mm/s of a speed-ramp set; 0: the material's
  MeanStd lambda1, lambda2, lambda3, contraction_pct;
  std::optional<MeanStd> curvature, delta_lambda1;  // when every sample has a curvature
};

// Per set, in the order of the sheet. Sets with no measured sample are left out.
std::vector<SetFit> fit_sets(const MeasurementSheet& sheet);

// Best first: the highest mean contraction (Shrink & Morph §4.1 keeps the set that shrinks most),
// then the smaller spread, then the smaller set id.
void rank_sets(std::vector<SetFit>& sets);

// `base` (the material the samples were printed with) with the set's ratios, Delta lambda1 (when
// measured; otherwise base's), layer height, nozzle temperature and, for a speed-ramp set, print
// speed (the ratios hold at the speed they were measured at); without the base's thickness and
// speed curves, which the caller replaces by those of the ramps it fitted (its hinge curve, fold
// angles measured on their own strips, stays unless the caller fits another). Throws
// UserError(kFormat) when a ratio lies outside what a material file accepts.
Material fitted_material(const Material& base, const SetFit& set, const std::string& name,
                         const std::string& description);

// The polynomial lambda1(h) of degree at most `max_degree` (<= 4) fitting the samples of a
// thickness-ramp sheet by least squares: the highest degree that the distinct layer heights
// support and that is strictly monotone on their range. Throws UserError(kFormat) with fewer than
// two distinct layer heights, or when lambda1 does not change with the layer height.
ThicknessCurve fit_thickness_curve(const MeasurementSheet& sheet, int max_degree = 4);

// The same from plain data: layer heights (mm) and lambda1 per sample.
ThicknessCurve fit_thickness_curve(const std::vector<double>& layer_heights,
                                   const std::vector<double>& lambda1, int layers,
                                   double nozzle_temperature, int max_degree = 4);

// The polynomial lambda1(v) fitting the samples of a speed-ramp sheet, by the rule of
// fit_thickness_curve (v: the sheet's print_speed column, mm/s). Throws UserError(kFormat) with
// fewer than two distinct speeds, or when lambda1 does not change with the speed.
SpeedCurve fit_speed_curve(const MeasurementSheet& sheet, int max_degree = 4);

// The same from plain data: print speeds (mm/s) and lambda1 per sample.
SpeedCurve fit_speed_curve(const std::vector<double>& print_speeds,
                           const std::vector<double>& lambda1, double layer_height,
                           double nozzle_temperature, int max_degree = 4);

// Contraction (%) versus layer height (mm) of the sets that are not from a speed ramp, one curve
// per nozzle temperature with error bars of one standard deviation, like Shrink & Morph Fig. 8;
// with `curve`, its contraction 100 (1 - lambda1(h)) over its range, dashed. SVG text.
std::string contraction_plot_svg(const std::vector<SetFit>& sets,
                                 const std::optional<ThicknessCurve>& curve);

// Contraction (%) versus print speed (mm/s) of the speed-ramp sets, drawn the same way, with
// `curve` dashed (Thermorph Fig. 6 plots the fold angle this contraction drives). SVG text.
std::string speed_contraction_plot_svg(const std::vector<SetFit>& sets,
                                       const std::optional<SpeedCurve>& curve);

}  // namespace flatmorph

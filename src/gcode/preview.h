// Pictures of a toolpath for people: one SVG per layer (polylines coloured by print order from dark
// blue to yellow, travels dashed grey, the plate outline if given) and a PNG overview with one
// panel per layer for a few layers or all of them. Plate coordinates (mm, as in flat.ply, x right,
// y up); the bytes depend only on the input.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "toolpath/toolpath.h"

namespace flatmorph {

// Where a layer's paths meet singularities (mm, plate frame): points where its print direction
// field has no direction (the paths turn around them) and points where its stripes fork (a path
// ends or begins inside the plate).
struct LayerSingularities {
  std::vector<Eigen::Vector2d> field;
  std::vector<Eigen::Vector2d> forks;
};

struct PreviewOptions {
  // Boundary loops of the plate (#P x 2, mm, plate frame), drawn under the paths; empty: none.
  std::vector<Eigen::MatrixX2d> outline;
  // Per layer, bottom first, drawn over the paths: field singularities as red circles, stripe
  // forks as orange squares; empty (or shorter than the toolpath): none for those layers.
  std::vector<LayerSingularities> singularities;
  bool travels = true;     // draw the travels between polylines (dashed)
  int panel_pixels = 400;  // PNG: side of one layer's panel, pixels
  int max_panels = 12;     // PNG: at most this many layers, evenly spaced, first and last included
};

// The SVG picture of layer `layer` (0 = on the bed). Every layer of a toolpath gets the same
// drawing area, so that the pictures line up. Sizes in mm (1:1 when printed).
std::string layer_svg(const Toolpath& toolpath, size_t layer, const PreviewOptions& options = {});

// Writes layer_001.svg, layer_002.svg, ... (bottom first) into `folder`, created complete under a
// temporary name and renamed into place; it replaces an earlier `folder` and what was in it.
void write_layer_svgs(const std::filesystem::path& folder, const Toolpath& toolpath,
                      const PreviewOptions& options = {});

// The layers the overview shows (indices, bottom first).
std::vector<size_t> overview_layers(size_t layer_count, int max_panels);

// A PNG (RGB, 8 bits) with one panel per shown layer, left to right then top to bottom, each
// numbered with its layer (1 = on the bed).
std::vector<unsigned char> overview_png(const Toolpath& toolpath,
                                        const PreviewOptions& options = {});

void write_overview_png(const std::filesystem::path& path, const Toolpath& toolpath,
                        const PreviewOptions& options = {});

}  // namespace flatmorph

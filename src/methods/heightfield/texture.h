// Colour texture of a self-rising sheet (SCF 2020 §6.5 "Color Mapping", §7.1-7.2): the target
// height field's colours (per-vertex colours of a PLY, or an OBJ's texture coordinates into a PNG),
// the colour at any point of the field, and the screen-print image of the flat sheet: each pixel
// coloured from its flattened triangle, with the ink thinned where the sheet will shrink so that
// the risen surface shows the designed colours. Units: millimetres; colours in [0, 1].
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "methods/heightfield/color_image.h"
#include "methods/heightfield/height_field.h"
#include "raster/raster.h"

namespace flatmorph {

// ---------------------------------------------------------------------------------------------
// Colour input

// Colours at points of a mesh file, before the mesh became a height field (which welds vertices
// split along texture seams and drops unused ones): with_colors puts them on the field's vertices
// by position.
struct ColorSamples {
  Eigen::MatrixXd points;  // #S x 3, the file's coordinates (those height_field_from_mesh keeps)
  Eigen::MatrixXd colors;  // #S x 3, channels in [0, 1]
};

// The per-vertex colours of a PLY, as read_mesh reads its vertices: the vertex properties red,
// green, blue (or diffuse_red, diffuse_green, diffuse_blue). Their scale follows their declared
// type: float and double are already in [0, 1]; 8-bit types (uchar, char, uint8, int8) are divided
// by 255, 16-bit ones by 65535, and 32-bit integers, which writers use for 0-255, by 255. Alpha is
// ignored. Throws UserError naming the file: what read_mesh throws; kFormat when the PLY has no
// such colours (what to do: export with vertex colours, or use an OBJ and its texture) or a colour
// lies outside its range after scaling (which vertex).
ColorSamples read_ply_vertex_colors(const std::filesystem::path& ply);

// The colours an OBJ's texture gives its vertices: every distinct (v, vt) pair used by a face
// corner (`f v/vt ...`, `f v/vt/vn ...`) samples `image` at its texture coordinates with
// sample_bilinear (u right, v up; see there), at the position of v. A vertex split along a
// texture seam thus gives one sample per side, which with_colors averages. Unlike the authors'
// code (which reads pixel column (1 - u)(W - 1), mirroring the image) u is not flipped: u = 0 is
// the image's left edge in the OBJ convention every exporter follows. Throws UserError naming the
// OBJ: what read_mesh throws for a broken `v` or `f` line (kFormat, with its line); kFormat when
// the file has no texture coordinates (`vt` lines) or a face has a corner without one (which
// line), or a `vt` line is malformed or a face refers to a `vt` that does not exist.
ColorSamples read_obj_texture_colors(const std::filesystem::path& obj, const ColorImage& image);

// The field with the samples' colours on its vertices: each field vertex takes the mean colour of
// the samples within 1e-6 of the samples' bounding-box diagonal of its position (the welding of
// height_field_from_mesh is 1000 times finer). `source` names the colour file in messages. Throws
// UserError(kGeometry) when a field vertex has no sample there (the colours come from another
// mesh, or one scaled differently: "vertex at (x, y, z) has no colour ..."), std::invalid_argument
// when the samples' sizes disagree.
HeightField with_colors(HeightField field, const ColorSamples& samples, const std::string& source);

// with_colors from a file: a PLY's vertex colours (`image` must be empty), or an OBJ's texture
// coordinates into the PNG `image` (read_color_png). The field must have been made from the same
// file (height_field_from_mesh(read_mesh(mesh).mesh, ...), unscaled). Throws UserError: kOption
// for an OBJ without an image or a PLY with one, or a mesh that is neither (what to give instead);
// what the readers above throw.
HeightField with_texture(HeightField field, const std::filesystem::path& mesh,
                         const std::filesystem::path& image = {});

// The field's colour at points (x, y) (mm, #P x 2 or more columns: the first two are used): the
// colours of the face containing the point seen from above (the field is a graph over xy),
// interpolated barycentrically. For carrying colours onto the printing graph (IsolineMesh::V),
// whose vertices lie on the field. A point outside the footprint by at most 1e-4 of the field's
// xy diagonal (rounding on the boundary) takes the colour of the nearest point of the footprint.
// Throws std::invalid_argument when the field has no colours or a point is farther outside, or
// not finite.
Eigen::MatrixXd colors_at(const HeightField& field, const Eigen::MatrixXd& points_xy);

// ---------------------------------------------------------------------------------------------
// Screen-print image

// Where an image lies on the plate: pixel (x, y) (x right, y down from the top row) covers the
// square of side pixel_mm whose top-left corner is (left_mm + x pixel_mm, top_mm - y pixel_mm)
// in plate coordinates (mm, x right, y up, as the flat plate). Seen from above, not mirrored.
struct RasterPlacement {
  double left_mm = 0.0;
  double top_mm = 0.0;
  double pixel_mm = 25.4 / 300.0;
  int width = 0;   // pixels
  int height = 0;  // pixels

  Eigen::Vector2d pixel_center(int x, int y) const {
    return Eigen::Vector2d(left_mm + (x + 0.5) * pixel_mm, top_mm - (y + 0.5) * pixel_mm);
  }
};

// Sizes of a registration mark: a circle with a cross through its centre, black lines.
inline constexpr double kMarkRadiusMm = 3.5;  // of the circle
inline constexpr double kMarkArmMm = 5.0;     // half-length of each line of the cross
inline constexpr double kMarkLineMm = 0.25;   // line width (at least one pixel)
inline constexpr double kMarkGapMm = 2.0;     // between the sheet's bounding box and a mark
// How far the marks reach beyond the sheet's bounding box: the least margin that holds them.
inline constexpr double kMarkReachMm = kMarkGapMm + 2.0 * kMarkArmMm;

struct ScreenPrintOptions {
  double dpi = 300.0;       // print resolution: 1 pixel = 25.4 / dpi mm
  double margin_mm = 15.0;  // white border around the sheet's bounding box
  bool registration_marks = true;
};

struct ScreenPrint {
  RasterPlacement placement;
  double dpi = 300.0;
  Canvas image{0, 0};  // RGB, 8 bits, placement.width x placement.height
  // Per face of the sheet: the ink opacity α_f = clamp(a_t / a_f, 0, 1) (paper §6.5).
  Eigen::VectorXd opacity;
  // Centres of the registration marks in plate coordinates (mm): outside the sheet's bounding box
  // by kMarkGapMm (clear of the circle and the cross), beyond its top-left, top-right and
  // bottom-left corners, in that order (three, not four: the screen cannot be put on turned by
  // 180 degrees). Empty when the marks are off.
  std::vector<Eigen::Vector2d> marks;
};

// The screen-print image of the flat sheet at print scale: the bounding box of `plate` (#V x 2,
// mm, the flattened sheet) plus margin_mm on every side, 1 pixel = 25.4 / dpi mm. A pixel whose
// centre lies in a face f of the plate gets the colour c interpolated barycentrically from the
// face's corners' `colors` (#V x 3 in [0, 1]), thinned by the face's opacity
// α_f = clamp(a_t / a_f, 0, 1), with a_t its area on `target` (#V x 3, mm, the same faces F) and
// a_f its area on the plate, and composited on the white sheet: c' = 1 - α_f (1 - c) per channel.
// Why: the sheet shrinks as it rises, so a face's ink, printed over a_f, ends up concentrated on
// a_t and looks darker by a_f / a_t (paper Fig. 10); printing it at density a_t / a_f gives the
// designed density on the risen surface. The model treats ink as coverage over white (a halftone
// dot area), clamped at 1 where a face grows, since ink cannot be denser than solid. Pixels on no
// face (outside the sheet) are white; where faces of the plate overlap, the later face wins.
// Faces counter-clockwise or clockwise alike; a pixel centre on an edge shared by two faces is
// drawn once. Registration marks (black) are drawn unless turned off. Deterministic.
// Throws UserError(kOption) when dpi is not in (0, 2400], the margin is negative or smaller than
// kMarkReachMm with marks on, or the image would have more than kMaxGrayImagePixels pixels (lower
// the dpi); std::invalid_argument when sizes disagree, an index is out of range, a coordinate is
// not finite or a colour is outside [0, 1].
ScreenPrint render_screen_print(const Eigen::MatrixXd& plate, const Eigen::MatrixXd& target,
                                const Eigen::MatrixXi& F, const Eigen::MatrixXd& colors,
                                const ScreenPrintOptions& options = {});

// The PNG file of the image (RGB, 8 bits), with a pHYs chunk giving its resolution (pixels per
// metre = round(dpi / 0.0254)) so that it prints at scale. Bytes depend only on the print.
std::vector<unsigned char> screen_print_png(const ScreenPrint& print);

// Writes screen_print_png atomically (common/atomic_file.h). Throws UserError(kFile) when the file
// cannot be written.
void write_screen_print_png(const std::filesystem::path& path, const ScreenPrint& print);

// ---------------------------------------------------------------------------------------------
// Checkerboard acceptance (issue 23): a checkerboard printed on the flat sheet, mapped through the
// risen shape, must keep the squares' areas on the target.

// Per pixel of a placement, which square of a checkerboard of side square_mm in the target's xy
// the design puts there: the pixel centre's position in its face of `plate` (the plate the image
// was rendered with), carried barycentrically to the same face of `target`, gives the square
// (floor(x / s), floor(y / s)). The label image rendered alongside a screen print (same placement
// and the same pixel coverage as render_screen_print).
struct SquareLabels {
  RasterPlacement placement;
  std::vector<int> labels;               // per pixel, row-major from the top; -1 off the sheet
  std::vector<Eigen::Vector2i> squares;  // label -> (i, j), sorted by (i, j)
};
SquareLabels checkerboard_labels(const RasterPlacement& placement, const Eigen::MatrixXd& plate,
                                 const Eigen::MatrixXd& target, const Eigen::MatrixXi& F,
                                 double square_mm);

// The area (mm^2) each label covers on the risen surface when the image is printed on the sheet
// `plate` (#V x 2, mm) that rises into `risen` (#V x 3, mm, same faces F): every labelled pixel
// whose centre lies in a face f of the plate counts pixel_mm^2 times the face's area ratio
// risen / flat; pixels off the sheet count nothing.
Eigen::VectorXd risen_label_areas(const SquareLabels& labels, const Eigen::MatrixXd& plate,
                                  const Eigen::MatrixXd& risen, const Eigen::MatrixXi& F);

// The exact area (mm^2) of each square on the target surface (#V x 3): each face's xy projection
// clipped to the square, times the face's area over its xy area.
Eigen::VectorXd target_square_areas(const Eigen::MatrixXd& target, const Eigen::MatrixXi& F,
                                    double square_mm, const std::vector<Eigen::Vector2i>& squares);

struct CheckerboardCheck {
  int squares_compared = 0;
  double worst_relative_error = 0.0;  // max over compared squares of |risen - target| / target
  Eigen::Vector2i worst_square = Eigen::Vector2i::Zero();
  double worst_target_mm2 = 0.0, worst_risen_mm2 = 0.0;
};

// Compares risen_label_areas with target_square_areas over every square whose target area is at
// least min_fraction of a whole square (boundary slivers are dominated by pixel rounding). A square
// on the target that the labels miss counts as risen area 0.
CheckerboardCheck check_checkerboard(const SquareLabels& labels, const Eigen::MatrixXd& plate,
                                     const Eigen::MatrixXd& target, const Eigen::MatrixXd& risen,
                                     const Eigen::MatrixXi& F, double square_mm,
                                     double min_fraction = 0.25);

}  // namespace flatmorph

// Reading drawings saved as SVG, for the readers of drawn input (tile outlines, crease patterns):
// the XML, the root's size and viewBox in millimetres, SVG's y turned up so that nothing is
// mirrored, the transforms of groups and elements, hidden and non-drawing elements left out, and
// the numbers, lengths, point lists and path data of the shapes. What a shape means is the
// caller's: each reader takes the elements it understands and refuses the others in its own words.
// Every problem is a UserError with one line "SOURCE:LINE: problem: what to do".
#pragma once

#include <Eigen/Core>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/error.h"

namespace flatmorph::svg {

using Point = Eigen::Vector2d;

// An affine map p -> linear p + offset.
struct Affine {
  Eigen::Matrix2d linear = Eigen::Matrix2d::Identity();
  Point offset = Point::Zero();

  Point operator()(const Point& p) const { return linear * p + offset; }
  // This map after `inner`.
  Affine after(const Affine& inner) const {
    return {linear * inner.linear, linear * inner.offset + offset};
  }
};

struct Attribute {
  std::string_view name;  // as written (a view into the drawing's text)
  std::string value;      // the five predefined entities and character references decoded
};

struct Element {
  std::string_view name;  // as written, e.g. "path" or "svg:path"
  std::vector<Attribute> attributes;
  long long line = 0;  // where its tag starts, from 1

  const std::string* find(std::string_view key) const;
};

// An element that draws, as read_drawing hands it over: not the root, a group (<g>, <a>), a
// hidden element (display:none, as an attribute or in its style), or anything inside <defs>,
// <text>, <style>, <title>, <desc>, <metadata>, <symbol>, <marker>, <pattern>, <clipPath>, <mask>,
// gradients, filters, scripts, fonts, animations or another namespace (sodipodi:*, inkscape:*);
// nor the children of a shape.
struct Shape {
  const Element& element;
  std::string_view name;  // the element's name without an "svg:" prefix
  // Its user units to mm in plate coordinates (x right, y up, seen from above): the root's
  // viewport, then the transforms of the groups around it and its own.
  const Affine& map;
  // The root <svg> and the groups around the shape, outermost first (for inherited styles).
  const std::vector<Element>& groups;
};

// Calls `shape` with every element of the SVG `text` that draws, in document order. `source`
// names the file in messages; `content` says what the file should hold ("the outlines"). The
// drawing's size: with a viewBox, width/height in mm, cm, in, pt, pc or px (CSS px = 25.4/96 mm,
// also for unitless) scale user units to mm (preserveAspectRatio honoured); without a viewBox one
// user unit is one CSS px; with neither width/height nor viewBox, one mm (with a warning). Plate
// y = −SVG y. Warnings (what was assumed or left out, e.g. hidden elements) go to `warnings`.
//
// Throws UserError(kFormat) for an empty, compressed (.svgz) or UTF-16 file, malformed XML (with
// the line), elements nested deeper than 256, a root that is not <svg>, and bad sizes, viewBoxes
// or transforms; and whatever `shape` throws.
void read_drawing(std::string_view text, const std::string& source, std::string_view content,
                  const std::function<void(const Shape&)>& shape,
                  std::vector<std::string>& warnings);

// "<path id=\"p2\">" (or "<path>"), naming an element in messages.
std::string describe(const Element& element);

// Throws UserError(category, "SOURCE:LINE: message") for the element's line.
[[noreturn]] void fail(const std::string& source, const Element& element,
                       const std::string& message, ErrorCategory category = ErrorCategory::kFormat);

// The whole of `text` as one SVG number (spaces around it allowed); nullopt if it is not one or
// is not finite.
std::optional<double> number(std::string_view text);

// The attribute `key` of the element as a length in its user units: a number with an optional
// absolute unit (mm, cm, in, pt, pc, px). nullopt when it is missing; throws UserError(kFormat)
// when it is not a length or has another unit (%, em).
std::optional<double> length(const Element& element, std::string_view key,
                             const std::string& source);

// The value of the CSS property `name` of the element: its style attribute wins over its
// presentation attribute (stroke="red"); when `inherited` and the element sets neither, the
// nearest group around the shape that does. Trimmed, as written (no case folding); nullopt when
// nothing sets it or it says "inherit" all the way up.
std::optional<std::string> property(const Shape& shape, std::string_view name, bool inherited);

// Calls `point` with each point of the element's `points` attribute (<polygon>, <polyline>), in
// user units. Throws UserError(kFormat) for something that is not a number or an odd count.
void read_points(const Element& element, const std::string& source,
                 const std::function<void(const Point&)>& point);

// An elliptical arc command's parameters (SVG 1.1 F.6.5), user units and degrees as written.
struct ArcCommand {
  double rx = 0, ry = 0;
  double rotation = 0;  // degrees
  bool large = false, sweep = false;
};

// What a path's data draw, in user units, command by command. A subpath begins at a moveto or at
// a drawing command after a closepath (from the last subpath's start), and ends at the next
// moveto, at a closepath (closed) or at the end of the data; a lone moveto begins and ends one
// with nothing drawn. `subpath` counts them from 1.
struct PathCallbacks {
  std::function<void(const Point& start, int subpath)> begin;
  std::function<void(const Point& to)> line_to;
  std::function<void(const Point& from, const Point& to, const ArcCommand& arc)> arc_to;
  std::function<void(bool closed)> end;
};

// Reads the element's `d` (M, L, H, V, Z and A, absolute and relative) into `callbacks`. Throws
// UserError(kFormat) naming the command and its character: curves (C, S, Q, T: flatten them to
// line segments first), unknown commands, missing numbers, data that do not begin with a moveto,
// a number after Z.
void read_path(const Element& element, const std::string& source, const PathCallbacks& callbacks);

}  // namespace flatmorph::svg

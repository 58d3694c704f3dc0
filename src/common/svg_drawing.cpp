#include "common/svg_drawing.h"
#include "common/angles.h"

#include <fmt/core.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <numbers>

namespace flatmorph::svg {
namespace {

constexpr size_t kMaxDepth = 256;
constexpr double kMillimetresPerPx = 25.4 / 96;  // CSS

std::string where(const std::string& file, long long line) {
  return fmt::format("{}:{}", file, line);
}

// --- XML ---------------------------------------------------------------------------------------

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

bool is_name_start(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || c == '_' || c == ':' ||
         static_cast<unsigned char>(c) >= 0x80;
}

bool is_name_char(char c) {
  return is_name_start(c) || (c >= '0' && c <= '9') || c == '-' || c == '.';
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
  return s;
}

void append_utf8(std::string& out, unsigned long code) {
  if (code < 0x80) {
    out += static_cast<char>(code);
  } else if (code < 0x800) {
    out += static_cast<char>(0xc0 | code >> 6);
    out += static_cast<char>(0x80 | (code & 0x3f));
  } else if (code < 0x10000) {
    out += static_cast<char>(0xe0 | code >> 12);
    out += static_cast<char>(0x80 | (code >> 6 & 0x3f));
    out += static_cast<char>(0x80 | (code & 0x3f));
  } else {
    out += static_cast<char>(0xf0 | code >> 18);
    out += static_cast<char>(0x80 | (code >> 12 & 0x3f));
    out += static_cast<char>(0x80 | (code >> 6 & 0x3f));
    out += static_cast<char>(0x80 | (code & 0x3f));
  }
}

// Entities other than the predefined five and character references (declared in a DOCTYPE, as
// Illustrator does for namespaces) stay as written: no attribute read here uses them.
std::string decode_entities(std::string_view raw) {
  if (raw.find('&') == std::string_view::npos) return std::string(raw);
  std::string out;
  out.reserve(raw.size());
  for (size_t i = 0; i < raw.size(); ++i) {
    const size_t semicolon = raw[i] == '&' ? raw.find(';', i) : std::string_view::npos;
    if (semicolon == std::string_view::npos || semicolon - i > 10) {
      out += raw[i];
      continue;
    }
    const std::string_view name = raw.substr(i + 1, semicolon - i - 1);
    static constexpr std::pair<std::string_view, char> kPredefined[] = {
        {"lt", '<'}, {"gt", '>'}, {"amp", '&'}, {"quot", '"'}, {"apos", '\''}};
    bool done = false;
    for (const auto& [entity, c] : kPredefined) {
      if (name == entity) {
        out += c;
        done = true;
      }
    }
    if (!done && name.size() > 1 && name[0] == '#') {
      const bool hex = name[1] == 'x';
      const std::string_view digits = name.substr(hex ? 2 : 1);
      unsigned long code = 0;
      const auto [end, error] =
          std::from_chars(digits.data(), digits.data() + digits.size(), code, hex ? 16 : 10);
      if (!digits.empty() && error == std::errc() && end == digits.data() + digits.size() &&
          code > 0 && code <= 0x10ffff) {
        append_utf8(out, code);
        done = true;
      }
    }
    if (done) {
      i = semicolon;
    } else {
      out += raw[i];
    }
  }
  return out;
}

// A small XML reader for what SVG files hold: elements and attributes, with comments, processing
// instructions, the DOCTYPE (internal subset included), CDATA and text skipped. It calls
// handler.start(element) and handler.end() for each element, in document order.
template <typename Handler>
class XmlScanner {
 public:
  XmlScanner(std::string_view text, const std::string& file, Handler& handler)
      : text_(text), file_(file), handler_(handler) {}

  void scan() {
    bool root_seen = false;
    while (position_ < text_.size()) {
      if (text_[position_] != '<') {
        const size_t next = std::min(text_.find('<', position_), text_.size());
        if (open_.empty()) {
          for (size_t i = position_; i < next; ++i) {
            if (!is_space(text_[i])) {
              move_to(i);
              fail(root_seen ? "text after the root element: the file is damaged; save it "
                               "again as SVG"
                             : "text before the first element: not an SVG file; save the "
                               "drawing as SVG");
            }
          }
        }
        move_to(next);
        continue;
      }
      const std::string_view rest = text_.substr(position_);
      if (rest.substr(0, 4) == "<!--") {
        skip_past("-->", "comment");
      } else if (rest.substr(0, 2) == "<?") {
        skip_past("?>", "processing instruction (<?...?>)");
      } else if (rest.substr(0, 9) == "<![CDATA[") {
        if (open_.empty()) fail("a CDATA section outside the root element: the file is damaged");
        skip_past("]]>", "CDATA section");
      } else if (rest.substr(0, 9) == "<!DOCTYPE") {
        if (root_seen) fail("a DOCTYPE after the root element: the file is damaged");
        skip_doctype();
      } else if (rest.substr(0, 2) == "<!") {
        fail(
            "unknown markup (<! not followed by --, [CDATA[ or DOCTYPE): the file is damaged; "
            "save it again as SVG");
      } else if (rest.substr(0, 2) == "</") {
        end_tag();
      } else {
        if (open_.empty() && root_seen) {
          fail("a second root element: an XML file has one; save the drawing again as SVG");
        }
        root_seen = true;
        start_tag();
      }
    }
    if (!open_.empty()) {
      throw UserError(
          ErrorCategory::kFormat,
          fmt::format("{}: the file ends inside <{}> (opened at line {}): it is "
                      "truncated; save the drawing again as SVG",
                      where(file_, line_), printable(open_.back().first), open_.back().second));
    }
    if (!root_seen) {
      throw UserError(ErrorCategory::kFormat,
                      fmt::format("{}: no element at all: not an SVG file; save the drawing as "
                                  "SVG",
                                  file_));
    }
  }

 private:
  [[noreturn]] void fail(const std::string& message) const {
    throw UserError(ErrorCategory::kFormat, fmt::format("{}: {}", where(file_, line_), message));
  }

  void move_to(size_t position) {
    line_ += std::count(text_.begin() + static_cast<std::ptrdiff_t>(position_),
                        text_.begin() + static_cast<std::ptrdiff_t>(position), '\n');
    position_ = position;
  }

  void skip_past(std::string_view end, const char* what) {
    const size_t at = text_.find(end, position_);
    if (at == std::string_view::npos) {
      fail(fmt::format("a {} that is never closed (no {}): the file is truncated or damaged", what,
                       end));
    }
    move_to(at + end.size());
  }

  // <!DOCTYPE ...>, up to the '>' outside quotes and outside the [internal subset].
  void skip_doctype() {
    const long long start = line_;
    size_t i = position_;
    int brackets = 0;
    for (; i < text_.size(); ++i) {
      const char c = text_[i];
      if (c == '"' || c == '\'') {
        i = text_.find(c, i + 1);
        if (i == std::string_view::npos) break;
      } else if (c == '[') {
        ++brackets;
      } else if (c == ']') {
        --brackets;
      } else if (c == '>' && brackets <= 0) {
        move_to(i + 1);
        return;
      }
    }
    line_ = start;
    fail("a DOCTYPE that is never closed: the file is truncated or damaged");
  }

  void skip_spaces() {
    size_t i = position_;
    while (i < text_.size() && is_space(text_[i])) ++i;
    move_to(i);
  }

  std::string_view name(const char* what) {
    const size_t start = position_;
    if (start >= text_.size() || !is_name_start(text_[start])) {
      fail(fmt::format(
          "expected {} at {}: the file is not well-formed XML; save it again as SVG", what,
          start >= text_.size() ? std::string("the end of the file")
                                : fmt::format("\"{}\"", printable(text_.substr(start, 16)))));
    }
    size_t end = start;
    while (end < text_.size() && is_name_char(text_[end])) ++end;
    position_ = end;
    return text_.substr(start, end - start);
  }

  void start_tag() {
    const long long line = line_;
    ++position_;  // '<'
    Element element;
    element.name = name("an element name after <");
    element.line = line;
    bool closed = false;
    while (true) {
      const size_t before = position_;
      skip_spaces();
      if (position_ >= text_.size()) {
        line_ = line;
        fail(fmt::format("the tag <{}> is never closed (no >): the file is truncated",
                         printable(element.name)));
      }
      if (text_[position_] == '>') {
        ++position_;
        break;
      }
      if (text_.substr(position_, 2) == "/>") {
        position_ += 2;
        closed = true;
        break;
      }
      if (position_ == before) {
        fail(
            fmt::format("expected a space, > or /> in the tag <{}>, found \"{}\": the file is "
                        "not well-formed XML",
                        printable(element.name), printable(text_.substr(position_, 1))));
      }
      Attribute attribute;
      attribute.name = name("an attribute name");
      skip_spaces();
      if (position_ >= text_.size() || text_[position_] != '=') {
        fail(
            fmt::format("the attribute {} of <{}> has no = and value: the file is not "
                        "well-formed XML",
                        printable(attribute.name), printable(element.name)));
      }
      ++position_;
      skip_spaces();
      const char quote = position_ < text_.size() ? text_[position_] : '\0';
      if (quote != '"' && quote != '\'') {
        fail(
            fmt::format("the value of the attribute {} of <{}> is not in quotes: the file is "
                        "not well-formed XML",
                        printable(attribute.name), printable(element.name)));
      }
      const size_t end = text_.find(quote, position_ + 1);
      if (end == std::string_view::npos) {
        fail(
            fmt::format("the value of the attribute {} of <{}> is never closed (no {}): the "
                        "file is truncated or damaged",
                        printable(attribute.name), printable(element.name), quote));
      }
      const std::string_view raw = text_.substr(position_ + 1, end - position_ - 1);
      if (raw.find('<') != std::string_view::npos) {
        fail(
            fmt::format("the value of the attribute {} of <{}> holds a <: the file is not "
                        "well-formed XML (a quote missing?)",
                        printable(attribute.name), printable(element.name)));
      }
      attribute.value = decode_entities(raw);
      move_to(end + 1);
      element.attributes.push_back(std::move(attribute));
    }
    std::vector<std::string_view> names;
    for (const Attribute& a : element.attributes) names.push_back(a.name);
    std::sort(names.begin(), names.end());
    const auto twice = std::adjacent_find(names.begin(), names.end());
    if (twice != names.end()) {
      line_ = line;
      fail(fmt::format("the attribute {} appears twice in <{}>: the file is not well-formed XML",
                       printable(*twice), printable(element.name)));
    }
    if (open_.size() >= kMaxDepth) {
      line_ = line;
      fail(
          fmt::format("elements are nested more than {} deep: flatten the groups of the "
                      "drawing",
                      kMaxDepth));
    }
    open_.emplace_back(element.name, line);
    handler_.start(element);
    if (closed) {
      open_.pop_back();
      handler_.end();
    }
  }

  void end_tag() {
    position_ += 2;  // "</"
    const std::string_view closing = name("an element name after </");
    skip_spaces();
    if (position_ >= text_.size() || text_[position_] != '>') {
      fail(fmt::format("the end tag </{}> is not closed by >: the file is not well-formed XML",
                       printable(closing)));
    }
    ++position_;
    if (open_.empty()) {
      fail(fmt::format("</{}> closes no element: the file is not well-formed XML",
                       printable(closing)));
    }
    if (open_.back().first != closing) {
      fail(
          fmt::format("</{}> closes <{}> (opened at line {}): the file is not well-formed XML; "
                      "save it again as SVG",
                      printable(closing), printable(open_.back().first), open_.back().second));
    }
    open_.pop_back();
    handler_.end();
  }

  std::string_view text_;
  const std::string& file_;
  Handler& handler_;
  size_t position_ = 0;
  long long line_ = 1;
  std::vector<std::pair<std::string_view, long long>> open_;  // name, line
};

// --- SVG numbers, lengths and transforms -------------------------------------------------------

// Reads numbers the SVG way ("10-5" is two numbers, ".5.5" too), skipping spaces and commas.
struct NumberReader {
  std::string_view text;
  size_t position = 0;

  void skip_separators() {
    while (position < text.size() && (is_space(text[position]) || text[position] == ',')) {
      ++position;
    }
  }
  bool at_end() {
    skip_separators();
    return position >= text.size();
  }
  // Whether a number starts here (after separators).
  bool number_next() {
    skip_separators();
    if (position >= text.size()) return false;
    const char c = text[position];
    return (c >= '0' && c <= '9') || c == '.' || c == '-' || c == '+';
  }
  // false, leaving the position, when no number starts here.
  bool next(double& value) {
    if (!number_next()) return false;
    size_t i = position;
    if (text[i] == '+' || text[i] == '-') ++i;
    const size_t digits_start = i;
    while (i < text.size() && text[i] >= '0' && text[i] <= '9') ++i;
    size_t digits = i - digits_start;
    if (i < text.size() && text[i] == '.') {
      const size_t fraction = ++i;
      while (i < text.size() && text[i] >= '0' && text[i] <= '9') ++i;
      digits += i - fraction;
    }
    if (digits == 0) return false;
    if (i + 1 < text.size() && (text[i] == 'e' || text[i] == 'E')) {
      size_t j = i + 1;
      if (j < text.size() && (text[j] == '+' || text[j] == '-')) ++j;
      if (j < text.size() && text[j] >= '0' && text[j] <= '9') {
        while (j < text.size() && text[j] >= '0' && text[j] <= '9') ++j;
        i = j;
      }
    }
    std::string_view token = text.substr(position, i - position);
    if (token.front() == '+') token.remove_prefix(1);
    const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), value);
    if (error != std::errc() || end != token.data() + token.size() || !std::isfinite(value)) {
      return false;
    }
    position = i;
    return true;
  }
};

bool number_with_unit(std::string_view text, double& value, std::string& unit) {
  NumberReader reader{text};
  if (!reader.next(value)) return false;
  std::string_view rest = text.substr(reader.position);
  while (!rest.empty() && is_space(rest.back())) rest.remove_suffix(1);
  unit = std::string(rest);
  return rest.size() <= 2 || rest == "%";
}

// mm per unit: exact for the metric ones, so that a drawing sized in mm maps without rounding.
std::optional<double> unit_in_mm(std::string_view unit) {
  if (unit.empty() || unit == "px") return kMillimetresPerPx;
  if (unit == "mm") return 1.0;
  if (unit == "cm") return 10.0;
  if (unit == "in") return 25.4;
  if (unit == "pt") return 25.4 / 72;
  if (unit == "pc") return 25.4 / 6;
  return std::nullopt;
}

// The value of `name` in a style attribute ("a: 1; b: 2"), trimmed.
std::optional<std::string_view> style_item(std::string_view style, std::string_view name) {
  std::optional<std::string_view> found;
  while (!style.empty()) {
    const size_t semicolon = std::min(style.find(';'), style.size());
    const std::string_view item = style.substr(0, semicolon);
    style.remove_prefix(std::min(semicolon + 1, style.size()));
    const size_t colon = item.find(':');
    if (colon != std::string_view::npos && trim(item.substr(0, colon)) == name) {
      found = trim(item.substr(colon + 1));  // the last declaration wins
    }
  }
  return found;
}

bool hidden(const Element& element) {
  if (const std::string* display = element.find("display")) {
    if (trim(*display) == "none") return true;
  }
  if (const std::string* style = element.find("style")) {
    if (style_item(*style, "display") == std::string_view("none")) return true;
  }
  return false;
}

// Follows the drawing's structure: the root's viewport, groups and their transforms, what draws.
class DrawingWalker {
 public:
  DrawingWalker(const std::string& file, const std::function<void(const Shape&)>& shape,
                std::vector<std::string>& warnings)
      : file_(file), shape_(shape), warnings_(warnings) {}

  void finish() {
    if (hidden_ > 0) {
      warnings_.push_back(
          fmt::format("{}: {} hidden elements (display:none) are not read", file_, hidden_));
    }
  }

  void start(const Element& element) {
    if (frames_.empty()) {
      start_root(element);
      return;
    }
    const Frame& parent = frames_.back();
    if (parent.skip) {
      frames_.push_back({parent.map, true, false});
      return;
    }
    std::string_view name = element.name;
    if (name.substr(0, 4) == "svg:") name.remove_prefix(4);
    static constexpr std::string_view kIgnored[] = {"defs",
                                                    "style",
                                                    "title",
                                                    "desc",
                                                    "metadata",
                                                    "text",
                                                    "symbol",
                                                    "marker",
                                                    "pattern",
                                                    "clipPath",
                                                    "mask",
                                                    "linearGradient",
                                                    "radialGradient",
                                                    "filter",
                                                    "script",
                                                    "foreignObject",
                                                    "font",
                                                    "font-face",
                                                    "view",
                                                    "cursor",
                                                    "animate",
                                                    "animateTransform",
                                                    "animateMotion",
                                                    "animateColor",
                                                    "set",
                                                    "mpath",
                                                    "color-profile",
                                                    "meshgradient",
                                                    "hatch",
                                                    "solidcolor"};
    if (name.find(':') != std::string_view::npos ||
        std::find(std::begin(kIgnored), std::end(kIgnored), name) != std::end(kIgnored)) {
      frames_.push_back({parent.map, true, false});
      return;
    }
    if (hidden(element)) {
      ++hidden_;
      frames_.push_back({parent.map, true, false});
      return;
    }
    const Affine map = parent.map.after(transform(element));
    if (name == "g" || name == "a") {
      frames_.push_back({map, false, true});
      groups_.push_back(element);
      return;
    }
    // A shape's children (a <title>, an animation) draw nothing.
    frames_.push_back({map, true, false});
    shape_(Shape{element, name, frames_.back().map, groups_});
  }

  void end() {
    if (frames_.back().group) groups_.pop_back();
    frames_.pop_back();
  }

 private:
  struct Frame {
    Affine map;  // user units -> plate mm
    bool skip;   // nothing inside draws
    bool group;  // an element of groups_
  };

  [[noreturn]] void fail(const Element& element, const std::string& message) const {
    svg::fail(file_, element, message);
  }

  // The root's viewport: user units to mm (SVG's y down turned up).
  void start_root(const Element& element) {
    if (element.name != "svg" && element.name != "svg:svg") {
      fail(element, fmt::format("the root element is <{}>, not <svg>: not an SVG file; save the "
                                "drawing as SVG",
                                printable(element.name)));
    }
    const auto size_mm = [&](std::string_view key) -> std::optional<double> {
      const std::string* text = element.find(key);
      if (text == nullptr) return std::nullopt;
      double value = 0;
      std::string unit;
      if (!number_with_unit(*text, value, unit)) {
        fail(element, fmt::format("the drawing's {}=\"{}\" is not a length: give it in mm",
                                  printable(key), printable(*text)));
      }
      if (unit == "%") return std::nullopt;  // relative to a window: no physical size
      const std::optional<double> mm = unit_in_mm(unit);
      if (!mm) {
        fail(element, fmt::format("the drawing's {}=\"{}\" has a unit flatmorph cannot turn into "
                                  "millimetres: give it in mm",
                                  printable(key), printable(*text)));
      }
      if (!(value > 0)) {
        fail(element, fmt::format("the drawing's {}=\"{}\" is not positive: give the drawing's "
                                  "size in mm",
                                  printable(key), printable(*text)));
      }
      return value * *mm;
    };
    const std::optional<double> width = size_mm("width"), height = size_mm("height");
    Affine viewport;
    if (const std::string* view_box = element.find("viewBox")) {
      NumberReader reader{*view_box};
      double box[4];
      for (double& v : box) {
        if (!reader.next(v)) {
          fail(element, fmt::format("viewBox=\"{}\" is not four numbers (x y width height): fix "
                                    "it, and save again",
                                    printable(*view_box)));
        }
      }
      if (!reader.at_end() || !(box[2] > 0) || !(box[3] > 0)) {
        fail(element, fmt::format("viewBox=\"{}\" is not four numbers (x y width height) with a "
                                  "positive width and height: fix it, and save again",
                                  printable(*view_box)));
      }
      Point scale(1, 1), shift(0, 0);
      if (width && height) {
        scale = Point(*width / box[2], *height / box[3]);
        align(element, *width, *height, box[2], box[3], scale, shift);
      } else if (width || height) {
        scale.setConstant(width ? *width / box[2] : *height / box[3]);
      } else {
        warnings_.push_back(
            fmt::format("{}: the drawing has a viewBox but no width or height: "
                        "one user unit read as 1 mm",
                        file_));
      }
      viewport.linear = scale.asDiagonal();
      viewport.offset = shift - scale.cwiseProduct(Point(box[0], box[1]));
    } else if (width || height) {
      viewport.linear *= kMillimetresPerPx;  // without a viewBox user units are CSS px
    } else {
      warnings_.push_back(
          fmt::format("{}: the drawing has no width, height or viewBox: one user "
                      "unit read as 1 mm",
                      file_));
    }
    Affine flip;
    flip.linear(1, 1) = -1;
    frames_.push_back({flip.after(viewport), false, true});
    groups_.push_back(element);
  }

  // preserveAspectRatio (default xMidYMid meet): one scale for both axes unless "none", and the
  // viewBox aligned in the viewport.
  void align(const Element& element, double width, double height, double box_width,
             double box_height, Point& scale, Point& shift) const {
    std::string_view value = "xMidYMid meet";
    if (const std::string* given = element.find("preserveAspectRatio")) value = *given;
    NumberReader words{value};
    words.skip_separators();
    std::string_view rest = value.substr(words.position);
    const size_t space = std::min(rest.find(' '), rest.size());
    const std::string_view how = rest.substr(0, space);
    const bool slice = rest.substr(space).find("slice") != std::string_view::npos;
    if (how == "none") return;
    if (how.size() != 8 || how[0] != 'x' || how[4] != 'Y') {
      fail(element, fmt::format("preserveAspectRatio=\"{}\" is not understood: use none or "
                                "xMidYMid (meet or slice)",
                                printable(value)));
    }
    const auto fraction = [&](std::string_view where) {
      if (where == "Min") return 0.0;
      if (where == "Mid") return 0.5;
      if (where == "Max") return 1.0;
      fail(element, fmt::format("preserveAspectRatio=\"{}\" is not understood: use none or "
                                "xMidYMid (meet or slice)",
                                printable(value)));
    };
    const double s = slice ? std::max(scale.x(), scale.y()) : std::min(scale.x(), scale.y());
    shift = Point(fraction(how.substr(1, 3)) * (width - box_width * s),
                  fraction(how.substr(5, 3)) * (height - box_height * s));
    scale.setConstant(s);
  }

  Affine transform(const Element& element) const {
    Affine result;
    const std::string* text = element.find("transform");
    if (text == nullptr) return result;
    const auto bad = [&]() {
      fail(element, fmt::format("transform=\"{}\" of the {} is not a transform list (matrix, "
                                "translate, scale, rotate, skewX, skewY): fix it, and save again",
                                printable(*text), describe(element)));
    };
    NumberReader reader{*text};
    while (!reader.at_end()) {
      const size_t start = reader.position;
      size_t i = start;
      while (i < text->size() && std::isalpha(static_cast<unsigned char>((*text)[i]))) ++i;
      const std::string_view function = std::string_view(*text).substr(start, i - start);
      while (i < text->size() && is_space((*text)[i])) ++i;
      if (i >= text->size() || (*text)[i] != '(') bad();
      reader.position = i + 1;
      double v[6];
      int count = 0;
      while (count < 6 && reader.next(v[count])) ++count;
      reader.skip_separators();
      if (reader.position >= text->size() || (*text)[reader.position] != ')') bad();
      ++reader.position;
      Affine step;
      const auto radians = [](double degrees) { return degrees * kPi / 180; };
      if (function == "matrix" && count == 6) {
        step.linear << v[0], v[2], v[1], v[3];
        step.offset = Point(v[4], v[5]);
      } else if (function == "translate" && (count == 1 || count == 2)) {
        step.offset = Point(v[0], count == 2 ? v[1] : 0);
      } else if (function == "scale" && (count == 1 || count == 2)) {
        step.linear = Point(v[0], count == 2 ? v[1] : v[0]).asDiagonal();
      } else if (function == "rotate" && (count == 1 || count == 3)) {
        const double a = radians(v[0]);
        step.linear << std::cos(a), -std::sin(a), std::sin(a), std::cos(a);
        if (count == 3) {
          const Point centre(v[1], v[2]);
          step.offset = centre - step.linear * centre;
        }
      } else if (function == "skewX" && count == 1) {
        step.linear(0, 1) = std::tan(radians(v[0]));
      } else if (function == "skewY" && count == 1) {
        step.linear(1, 0) = std::tan(radians(v[0]));
      } else {
        bad();
      }
      result = result.after(step);
    }
    return result;
  }

  const std::string& file_;
  const std::function<void(const Shape&)>& shape_;
  std::vector<std::string>& warnings_;
  std::vector<Frame> frames_;
  std::vector<Element> groups_;
  long long hidden_ = 0;
};

}  // namespace

const std::string* Element::find(std::string_view key) const {
  for (const Attribute& a : attributes) {
    if (a.name == key) return &a.value;
  }
  return nullptr;
}

void read_drawing(std::string_view text, const std::string& source, std::string_view content,
                  const std::function<void(const Shape&)>& shape,
                  std::vector<std::string>& warnings) {
  if (text.find_first_not_of(" \t\r\n") == std::string_view::npos) {
    throw UserError(ErrorCategory::kFormat,
                    fmt::format("{}: empty file: save {} as SVG", source, content));
  }
  if (text.substr(0, 2) == "\x1f\x8b") {
    throw UserError(ErrorCategory::kFormat,
                    fmt::format("{}: a compressed SVG (.svgz), which flatmorph does not read: "
                                "save the drawing as plain SVG",
                                source));
  }
  if (text.substr(0, 2) == "\xff\xfe" || text.substr(0, 2) == "\xfe\xff") {
    throw UserError(ErrorCategory::kFormat,
                    fmt::format("{}: the file is in UTF-16, which flatmorph does not read: save "
                                "the drawing as SVG in UTF-8",
                                source));
  }
  if (text.substr(0, 3) == "\xef\xbb\xbf") text.remove_prefix(3);  // UTF-8 byte order mark
  DrawingWalker walker(source, shape, warnings);
  XmlScanner<DrawingWalker> scanner(text, source, walker);
  scanner.scan();
  walker.finish();
}

std::string describe(const Element& element) {
  const std::string* id = element.find("id");
  if (id == nullptr) return fmt::format("<{}>", printable(element.name));
  return fmt::format("<{} id=\"{}\">", printable(element.name), printable(*id));
}

void fail(const std::string& source, const Element& element, const std::string& message,
          ErrorCategory category) {
  throw UserError(category, fmt::format("{}: {}", where(source, element.line), message));
}

std::optional<double> number(std::string_view text) {
  NumberReader reader{trim(text)};
  double value = 0;
  if (!reader.next(value) || reader.position != reader.text.size()) return std::nullopt;
  return value;
}

std::optional<double> length(const Element& element, std::string_view key,
                             const std::string& source) {
  const std::string* text = element.find(key);
  if (text == nullptr) return std::nullopt;
  double value = 0;
  std::string unit;
  if (!number_with_unit(*text, value, unit)) {
    fail(source, element,
         fmt::format("{}=\"{}\" of the {} is not a length: give a number (with "
                     "mm, cm, in, pt, pc or px)",
                     printable(key), printable(*text), describe(element)));
  }
  const std::optional<double> mm_per_unit = unit_in_mm(unit);
  if (!mm_per_unit) {
    fail(source, element,
         fmt::format("{}=\"{}\" of the {} has a unit flatmorph cannot turn into "
                     "millimetres: give it in mm, cm, in, pt, pc or px",
                     printable(key), printable(*text), describe(element)));
  }
  return value * *mm_per_unit / kMillimetresPerPx;  // user units are CSS px
}

std::optional<std::string> property(const Shape& shape, std::string_view name, bool inherited) {
  const auto own = [&](const Element& element) -> std::optional<std::string_view> {
    if (const std::string* style = element.find("style")) {
      if (const auto item = style_item(*style, name)) return item;
    }
    if (const std::string* attribute = element.find(name)) return trim(*attribute);
    return std::nullopt;
  };
  std::optional<std::string_view> value = own(shape.element);
  for (auto group = shape.groups.rbegin();
       inherited && (!value || *value == "inherit") && group != shape.groups.rend(); ++group) {
    value = own(*group);
  }
  if (!value || *value == "inherit") return std::nullopt;
  return std::string(*value);
}

void read_points(const Element& element, const std::string& source,
                 const std::function<void(const Point&)>& point) {
  const std::string* points = element.find("points");
  NumberReader reader{points != nullptr ? std::string_view(*points) : std::string_view()};
  double xy[2];
  size_t count = 0;
  while (!reader.at_end()) {
    if (!reader.next(xy[count % 2])) {
      fail(source, element,
           fmt::format("the {}'s points hold \"{}\", which is not a number: fix the "
                       "shape, and save again",
                       describe(element), printable(reader.text.substr(reader.position, 16))));
    }
    if (++count % 2 == 0) point(Point(xy[0], xy[1]));
  }
  if (count % 2 != 0) {
    fail(source, element,
         fmt::format("the {}'s points hold an odd number of coordinates ({}): each "
                     "point needs an x and a y; fix the shape, and save again",
                     describe(element), count));
  }
}

void read_path(const Element& element, const std::string& source, const PathCallbacks& callbacks) {
  const std::string* d = element.find("d");
  const std::string what = describe(element);
  NumberReader reader{d != nullptr ? std::string_view(*d) : std::string_view()};
  bool drawing = false;  // a subpath is open
  int subpaths = 0;
  Point current(0, 0), start(0, 0);
  const auto begin_subpath = [&](const Point& at) {
    callbacks.begin(at, ++subpaths);
    drawing = true;
  };
  const auto end_subpath = [&](bool closed) {
    if (!drawing) return;
    drawing = false;
    callbacks.end(closed);
  };
  const auto bad = [&](const std::string& message) { fail(source, element, message); };
  char command = 0;
  while (!reader.at_end()) {
    const size_t at = reader.position;
    const char c = (*d)[at];
    if (std::isalpha(static_cast<unsigned char>(c))) {
      command = c;
      ++reader.position;
      if (std::string_view("CcSsQqTt").find(c) != std::string_view::npos) {
        bad(
            fmt::format("the {} has curves ({} command at character {} of d): "
                        "convert curves to line segments, e.g. Inkscape Extensions > "
                        "Modify Path > Flatten Beziers, and save again",
                        what, c, at + 1));
      }
      if (std::string_view("MmLlHhVvZzAa").find(c) == std::string_view::npos) {
        bad(
            fmt::format("the {} has an unknown command {} at character {} of d: "
                        "fix the path, and save again",
                        what, printable(std::string_view(&c, 1)), at + 1));
      }
      if (c == 'Z' || c == 'z') {
        end_subpath(true);
        current = start;
        continue;
      }
    } else if (command == 0) {
      bad(
          fmt::format("the {}'s data do not begin with a moveto (M or m): fix the "
                      "path, and save again",
                      what));
    } else if (command == 'Z' || command == 'z') {
      bad(
          fmt::format("the {} has a number after Z at character {} of d: fix the "
                      "path, and save again",
                      what, at + 1));
    }
    if (subpaths == 0 && command != 'M' && command != 'm') {
      bad(
          fmt::format("the {}'s data do not begin with a moveto (M or m): fix the "
                      "path, and save again",
                      what));
    }
    const bool relative = std::islower(static_cast<unsigned char>(command)) != 0;
    const Point base = relative ? current : Point(0, 0);
    const char upper = static_cast<char>(std::toupper(static_cast<unsigned char>(command)));
    const int needed = upper == 'A' ? 7 : (upper == 'H' || upper == 'V') ? 1 : 2;
    double v[7];
    for (int i = 0; i < needed; ++i) {
      const bool flag = upper == 'A' && (i == 3 || i == 4);
      bool ok;
      if (flag) {
        // Flags are one character each, separators optional ("0110 10").
        reader.skip_separators();
        ok = reader.position < d->size() &&
             ((*d)[reader.position] == '0' || (*d)[reader.position] == '1');
        if (ok) v[i] = (*d)[reader.position++] - '0';
      } else {
        ok = reader.next(v[i]);
      }
      if (!ok) {
        bad(
            fmt::format("the {}'s {} command at character {} of d needs {} "
                        "numbers{}, found {}: fix the path, and save again",
                        what, command, at + 1, needed,
                        upper == 'A' ? " (rx ry rotation large-arc sweep x y)" : "", i));
      }
    }
    Point target = current;
    if (upper == 'H') target.x() = v[0] + (relative ? current.x() : 0);
    if (upper == 'V') target.y() = v[0] + (relative ? current.y() : 0);
    if (upper == 'M' || upper == 'L') target = base + Point(v[0], v[1]);
    if (upper == 'A') target = base + Point(v[5], v[6]);
    if (upper == 'M') {
      end_subpath(false);
      start = target;
      begin_subpath(target);
      command = relative ? 'l' : 'L';  // more pairs after a moveto are linetos
    } else {
      if (!drawing) begin_subpath(current);  // after Z, from the subpath's start
      if (upper == 'A') {
        callbacks.arc_to(current, target, {v[0], v[1], v[2], v[3] != 0, v[4] != 0});
      } else {
        callbacks.line_to(target);
      }
    }
    current = target;
  }
  end_subpath(false);
}

}  // namespace flatmorph::svg

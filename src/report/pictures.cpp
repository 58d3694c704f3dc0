#include "report/pictures.h"

#include <fmt/core.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>

namespace flatmorph {
namespace {

constexpr int kSupersample = 2;
constexpr int kBarHeight = 56;  // pixels below the picture for the colour bar and its labels

// A horizontal colour bar from `color(t)`, t in [0, 1], with labels under its ends and middle.
template <class ColorFn>
void colour_bar(Canvas& canvas, int top, ColorFn color, const std::string& left,
                const std::string& middle, const std::string& right) {
  const int x0 = canvas.width / 8, x1 = canvas.width - canvas.width / 8;
  const int y0 = top + 10, y1 = top + 26;
  for (int x = x0; x < x1; ++x) {
    const Rgb c = to_rgb(color(static_cast<double>(x - x0) / std::max(1, x1 - x0 - 1)));
    canvas.rect(x, y0, x + 1, y1, c);
  }
  const Rgb black{0, 0, 0};
  const int scale = 3, ty = y1 + 6;
  draw_text(canvas, x0, ty, left, scale, black);
  draw_text(canvas, (x0 + x1 - text_width(middle, scale)) / 2, ty, middle, scale, black);
  draw_text(canvas, x1 - text_width(right, scale), ty, right, scale, black);
}

std::string label(double v) {
  std::string s = fmt::format("{:.3g}", v);
  return s == "-0" ? "0" : s;
}

}  // namespace

Canvas plate_picture(const Eigen::MatrixXd& P, const Eigen::MatrixXi& F,
                     const Eigen::VectorXd& values, PlateField field, int pixels) {
  Eigen::Vector2d lo(0, 0), hi(1, 1);
  if (P.rows() > 0) {
    lo = P.leftCols(2).colwise().minCoeff().transpose();
    hi = P.leftCols(2).colwise().maxCoeff().transpose();
  }
  const double size = std::max(1e-9, (hi - lo).maxCoeff());
  const int margin = pixels / 40;
  const double scale = (pixels - 2.0 * margin) / size;  // pixels per mm
  const int height = static_cast<int>(std::ceil((hi.y() - lo.y()) * scale)) + 2 * margin;
  const int s = kSupersample;
  Canvas big(pixels * s, height * s);
  auto to_pixel = [&](int v) {
    return Eigen::Vector3d(s * (margin + (P(v, 0) - lo.x()) * scale),
                           s * (margin + (hi.y() - P(v, 1)) * scale), 0);
  };
  const bool theta2 = field == PlateField::kTheta2 && values.size() == P.rows();
  const double max_theta2 = theta2 ? std::max(1e-12, values.cwiseAbs().maxCoeff()) : 1.0;
  const bool shrinkage = field == PlateField::kShrinkage && values.size() == F.rows();
  const double max_shrinkage =
      shrinkage && values.size() > 0 ? std::max(1e-12, values.maxCoeff()) : 1.0;
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    Eigen::Vector3d c[3];
    for (int k = 0; k < 3; ++k) {
      if (theta2) {
        c[k] = diverging_color(values[F(f, k)] / max_theta2);
      } else if (shrinkage) {
        c[k] = viridis(values[f] / max_shrinkage);
      } else {
        c[k] = cyclic_color(f < values.size() ? values[f] / std::numbers::pi : 0.0);
      }
    }
    big.triangle(to_pixel(F(f, 0)), to_pixel(F(f, 1)), to_pixel(F(f, 2)), c[0], c[1], c[2]);
  }
  Canvas small = downsampled(big, s);
  Canvas out(small.width, small.height + kBarHeight);
  std::copy(small.rgb.begin(), small.rgb.end(), out.rgb.begin());
  if (shrinkage) {
    colour_bar(
        out, small.height, [](double t) { return viridis(t); }, "0 %",
        label(50 * max_shrinkage) + " %", label(100 * max_shrinkage) + " %");
  } else if (theta2) {
    const double deg = max_theta2 * 180 / std::numbers::pi;
    colour_bar(
        out, small.height, [](double t) { return diverging_color(2 * t - 1); }, label(-deg), "0",
        label(deg));
  } else {
    colour_bar(
        out, small.height, [](double t) { return cyclic_color(t); }, "0", "90", "180");
  }
  return out;
}

Canvas shape_picture(const Eigen::MatrixXd& V, const Eigen::MatrixXi& F,
                     const Eigen::VectorXd& deviation_mm, int pixels) {
  // View: turned 30 degrees about z, then tilted 55 degrees so that we look down obliquely.
  const double az = 30 * std::numbers::pi / 180, tilt = 55 * std::numbers::pi / 180;
  const Eigen::Matrix3d Rz = Eigen::AngleAxisd(az, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Matrix3d Rx = Eigen::AngleAxisd(-tilt, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const Eigen::Matrix3d R = Rx * Rz;
  Eigen::MatrixXd Q(V.rows(), 3);
  for (Eigen::Index v = 0; v < V.rows(); ++v) Q.row(v) = (R * V.row(v).transpose()).transpose();
  Eigen::Vector3d lo(0, 0, 0), hi(1, 1, 1);
  if (Q.rows() > 0) {
    lo = Q.colwise().minCoeff().transpose();
    hi = Q.colwise().maxCoeff().transpose();
  }
  const double size = std::max(1e-9, std::max(hi.x() - lo.x(), hi.y() - lo.y()));
  const int margin = pixels / 40;
  const double scale = (pixels - 2.0 * margin) / size;
  const int height = static_cast<int>(std::ceil((hi.y() - lo.y()) * scale)) + 2 * margin;
  const int s = kSupersample;
  Canvas big(pixels * s, height * s);
  auto to_pixel = [&](int v) {
    // Screen y down; nearer (larger z after the rotation) means smaller depth.
    return Eigen::Vector3d(s * (margin + (Q(v, 0) - lo.x()) * scale),
                           s * (margin + (hi.y() - Q(v, 1)) * scale), -Q(v, 2));
  };
  const bool coloured = deviation_mm.size() == V.rows() && V.rows() > 0;
  const double max_dev = coloured ? std::max(1e-12, deviation_mm.maxCoeff()) : 1.0;
  const Eigen::Vector3d light = Eigen::Vector3d(-0.3, 0.4, 1).normalized();
  for (Eigen::Index f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d a = Q.row(F(f, 0)), b = Q.row(F(f, 1)), c = Q.row(F(f, 2));
    const Eigen::Vector3d n = (b - a).cross(c - a);
    const double shade = n.norm() > 0 ? 0.35 + 0.65 * std::abs(n.normalized().dot(light)) : 1.0;
    Eigen::Vector3d col[3];
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d base =
          coloured ? viridis(deviation_mm[F(f, k)] / max_dev) : Eigen::Vector3d(0.75, 0.75, 0.75);
      col[k] = base * shade;
    }
    big.triangle(to_pixel(F(f, 0)), to_pixel(F(f, 1)), to_pixel(F(f, 2)), col[0], col[1], col[2]);
  }
  Canvas small = downsampled(big, s);
  Canvas out(small.width, small.height + (coloured ? kBarHeight : 0));
  std::copy(small.rgb.begin(), small.rgb.end(), out.rgb.begin());
  if (coloured) {
    colour_bar(
        out, small.height, [](double t) { return viridis(t); }, "0", label(max_dev / 2),
        label(max_dev));
  }
  return out;
}

}  // namespace flatmorph

// Print-time estimate the way a firmware planner moves: each move accelerates, cruises and
// decelerates (a trapezoidal velocity profile), and passes through the junction with the next move
// at the speed the cornering model allows. Lengths in mm, speeds in mm/s, accelerations in mm/s^2,
// times in seconds.
#pragma once

#include <Eigen/Core>
#include <span>
#include <string>

#include "gcode/printer_profile.h"

namespace flatmorph {

struct MotionLimits {
  double print_acceleration = 1000;   // mm/s^2, moves that extrude
  double travel_acceleration = 1000;  // mm/s^2, all other moves (travels, z, retractions)
  CorneringModel cornering = CorneringModel::kJunctionDeviation;
  double junction_deviation = 0.013;  // mm
  double jerk = 8;                    // mm/s
};

MotionLimits motion_limits(const PrinterProfile& printer);

// One planner move: a straight displacement of the head, and/or filament pushed (e > 0) or pulled
// (e < 0). A move with no displacement moves the filament alone (retraction), over |e| mm.
struct Motion {
  Eigen::Vector3d delta = Eigen::Vector3d::Zero();  // mm
  double e = 0;                                     // mm of filament
  double speed = 0;                                 // mm/s, the requested (nominal) speed
};

// Time to execute `motions` in order, starting and ending at rest (seconds). Extruding moves (e > 0
// with a displacement) accelerate at print_acceleration, the others at travel_acceleration. The
// speed through the junction of two moves is at most the nominal speed of both, the cornering
// limit (junction deviation: v^2 = a delta sin(theta/2) / (1 - sin(theta/2)), theta the angle
// between the two directions' opposites as in Marlin and grbl; jerk: the per-axis speed change at
// most `jerk`), and what acceleration over the moves before and after allows (planner's backward
// and forward passes). Filament-only moves start and end at rest.
double estimate_time(std::span<const Motion> motions, const MotionLimits& limits);

// Trapezoidal profile of one move of `length` mm: entry speed v0, cruise speed v, exit speed v1
// (mm/s), acceleration a (mm/s^2); v0, v1 <= v and reachable. Seconds.
double trapezoid_time(double length, double v0, double v, double v1, double a);

// "1d 2h 3m 4s", "2h 0m 5s", "3m 0s", "12s": PrusaSlicer's form for the estimated time.
std::string format_duration(double seconds);

}  // namespace flatmorph

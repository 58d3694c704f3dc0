// The report of a design run: report.html, one self-contained offline page (the viewer bundled
// from web/ at build time, the run's data inlined) with the target and predicted shape in 3D, the
// plate coloured by theta1 or theta2, the print paths layer by layer and every metric; and PNG
// pictures of the plate, the layers and the predicted shape. docs/report.md.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "report/run_folder.h"

namespace flatmorph {

// The page for a run folder. Same folder content, same bytes.
std::string report_html(const RunFolder& run);

// Writes, into run.dir, the pictures that the folder's files allow: plate_theta1.png,
// plate_theta2.png (when theta2 is non-zero), predicted.png (predicted shape coloured by
// deviation_mm), layers.png (a montage of the layers of plate.gcode). `pixels` is the width of the
// plate and shape pictures (a layer's panel in the montage is 3/8 of it). Returns the files
// written.
inline constexpr int kReportPicturePixels = 800;
std::vector<std::filesystem::path> write_report_pictures(const RunFolder& run,
                                                         int pixels = kReportPicturePixels);

// Reads the run folder and writes run_dir/report.html and the pictures; returns the files written
// (report.html first), the pictures `pixels` wide. `name` is the folder's name the page shows
// (empty: run_dir's; a run written into a temporary folder first gives the name it will have).
// Throws UserError naming the folder or file when the folder cannot be read.
std::vector<std::filesystem::path> write_report(const std::filesystem::path& run_dir,
                                                const std::string& name = "",
                                                int pixels = kReportPicturePixels);

}  // namespace flatmorph

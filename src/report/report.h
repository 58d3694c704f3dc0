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
// deviation_mm), layers.png (a montage of the layers of plate.gcode). Returns the files written.
std::vector<std::filesystem::path> write_report_pictures(const RunFolder& run);

// Reads the run folder and writes run_dir/report.html and the pictures; returns the files written
// (report.html first). `name` is the folder's name the page shows (empty: run_dir's; a run
// written into a temporary folder first gives the name it will have). Throws UserError naming the
// folder or file when the folder cannot be read.
std::vector<std::filesystem::path> write_report(const std::filesystem::path& run_dir,
                                                const std::string& name = "");

}  // namespace flatmorph

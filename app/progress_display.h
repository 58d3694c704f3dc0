// Shows the library's progress reports (common/progress.h) on stdout, so that stderr holds only
// errors and warnings: a line redrawn in place on a terminal, plain lines otherwise (logs, pipes),
// nothing with --quiet or --json.
#pragma once

#include "common/progress.h"

namespace flatmorph::cli {

// The callback for the current command; empty when `silent` (--quiet, --json). Elapsed time is
// counted from each stage's first report.
ProgressCallback make_progress_display(bool silent);

// Ends a line left open by the terminal display (call before printing anything else).
void finish_progress_line();

}  // namespace flatmorph::cli

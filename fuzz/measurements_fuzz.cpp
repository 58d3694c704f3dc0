// libFuzzer target for calibration measurement sheets (parse_measurements, the CSV that
// `flatmorph calibrate fit` reads): any bytes give a sheet or a UserError, nothing else. A sheet
// that parses is also turned into per-sample ratios and fitted, as the command does.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "calibration/fit.h"
#include "calibration/measurements.h"
#include "common/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace flatmorph;
  try {
    const MeasurementSheet sheet =
        parse_measurements(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz");
    sample_ratios(sheet);
    fit_sets(sheet);
  } catch (const UserError&) {
  }
  return 0;
}

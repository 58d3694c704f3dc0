// Cooperative cancellation of long work (a design in the studio, a run started from Python): the
// caller sets the token from any thread, and the work stops at its next progress report by
// throwing Cancelled, which unwinds like any error (outputs being written are abandoned).
#pragma once

#include <atomic>
#include <stdexcept>

namespace flatmorph {

class CancelToken {
 public:
  void cancel() { cancelled_.store(true, std::memory_order_relaxed); }
  bool cancelled() const { return cancelled_.load(std::memory_order_relaxed); }

 private:
  std::atomic<bool> cancelled_{false};
};

// Thrown where cancelled work stops; neither a UserError nor an internal failure.
class Cancelled : public std::runtime_error {
 public:
  Cancelled() : std::runtime_error("cancelled") {}
};

}  // namespace flatmorph

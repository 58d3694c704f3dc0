#include "numerics/sparse_cholesky.h"

#include <omp.h>

#include <mutex>

namespace flatmorph {

void configure_sparse_cholesky(SparseCholesky& solver) {
  cholmod_common& c = solver.cholmod();
  c.print = 0;
  c.nmethods = 2;
  c.method[0].ordering = CHOLMOD_AMD;
  c.method[1].ordering = CHOLMOD_METIS;
  c.postorder = 1;
}

void analyze_pattern(SparseCholesky& solver, const Eigen::SparseMatrix<double>& a) {
  static std::mutex metis;  // guards the process-wide state of a library, not of this project
  const std::lock_guard<std::mutex> lock(metis);
  solver.analyzePattern(a);
}

void factorize(SparseCholesky& solver, const Eigen::SparseMatrix<double>& a) {
  // With no active level allowed, every parallel region the calling thread meets runs on it alone.
  struct SerialOpenMp {
    int saved = omp_get_max_active_levels();
    SerialOpenMp() { omp_set_max_active_levels(0); }
    ~SerialOpenMp() { omp_set_max_active_levels(saved); }
  } serial_openmp;
  solver.factorize(a);
}

}  // namespace flatmorph

#include "numerics/sparse_cholesky.h"

#include <dlfcn.h>
#include <omp.h>

namespace flatmorph {

void configure_sparse_cholesky(SparseCholesky& solver) {
  cholmod_common& c = solver.cholmod();
  c.print = 0;
  c.nmethods = 2;
  c.method[0].ordering = CHOLMOD_AMD;
  c.method[1].ordering = CHOLMOD_METIS;
  c.postorder = 1;
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

void use_single_threaded_blas() {
  // Looked up at run time: the BLAS is whichever the system's alternatives select, and only
  // OpenBLAS has threads.
  using SetNumThreads = void (*)(int);
  const auto set = reinterpret_cast<SetNumThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  if (set) set(1);
}

}  // namespace flatmorph

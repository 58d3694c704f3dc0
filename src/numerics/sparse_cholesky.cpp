#include "numerics/sparse_cholesky.h"

namespace flatmorph {

void configure_sparse_cholesky(SparseCholesky& solver) {
  cholmod_common& c = solver.cholmod();
  c.print = 0;
  c.nmethods = 2;
  c.method[0].ordering = CHOLMOD_AMD;
  c.method[1].ordering = CHOLMOD_METIS;
  c.postorder = 1;
}

}  // namespace flatmorph

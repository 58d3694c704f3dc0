// The sparse Cholesky factorization of the project's large SPD systems (plate Hessians, stripe
// patterns): CHOLMOD's supernodal LLᵀ, whose dense blocks run on BLAS.
#pragma once

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCore>

namespace flatmorph {

using SparseCholesky = Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower>;

// Quiet (a failed factorization is expected, not news: callers test info() and fall back), and with
// the fill-reducing ordering chosen between AMD and METIS nested dissection by the fill it gives.
// CHOLMOD's default tries METIS only when AMD's fill is very high, and on large plate Hessians
// METIS needs fewer flops while AMD stays better on small ones (docs/design.md, "Speed"). The
// ordering is computed once per sparsity pattern, so trying both costs one extra analysis.
void configure_sparse_cholesky(SparseCholesky& solver);

// The symbolic analysis (fill-reducing ordering) of a's pattern. One at a time in the process:
// METIS, one of the orderings CHOLMOD tries, draws from a random generator the whole process
// shares, so two analyses at once (the design runs independent problems on both cores) would
// order, and round, differently from run to run.
void analyze_pattern(SparseCholesky& solver, const Eigen::SparseMatrix<double>& a);

// solver.factorize(a) with CHOLMOD's own OpenMP regions run by the calling thread alone. Debian's
// CHOLMOD 3 copies every large supernode into the factor with 4 OpenMP threads, a number fixed
// when it was compiled; on a 2-core machine whose cores TBB and BLAS threads already use, those
// regions cost more in thread wake-ups than they save (docs/design.md, "Speed"). The caller's
// OpenMP setting is restored afterwards.
void factorize(SparseCholesky& solver, const Eigen::SparseMatrix<double>& a);

}  // namespace flatmorph

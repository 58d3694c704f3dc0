// The sparse Cholesky factorization of the project's large SPD systems (plate Hessians, stripe
// patterns): CHOLMOD's supernodal LLᵀ, whose dense blocks run on BLAS.
#pragma once

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCore>

namespace flatmorph {

using SparseCholesky = Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower>;

// Quiet (a failed factorization is expected, not news: callers test info() and fall back), and with
// the fill-reducing ordering chosen between AMD and METIS nested dissection by the fill it gives.
// CHOLMOD's default tries METIS only when AMD's fill is very high; on the plate Hessians of the
// paper's 11008-face hat METIS needs 30 % fewer flops (1.6 instead of 2.3 GFlop, 0.11 instead of
// 0.13 s per factorization), while AMD stays better on the 2048-face saddle. The ordering is
// computed once per sparsity pattern, so trying both costs one extra analysis.
void configure_sparse_cholesky(SparseCholesky& solver);

// solver.factorize(a) with CHOLMOD's own OpenMP regions run by the calling thread alone. Debian's
// CHOLMOD 3 copies every large supernode into the factor with 4 OpenMP threads, a number fixed
// when it was compiled; on a 2-core machine whose cores TBB and BLAS threads already use, those
// regions cost more in thread wake-ups than they save (the paper's hat designed in 19.4 s instead
// of 11.5 s; docs/design.md, "Speed"). The caller's OpenMP setting is restored afterwards.
void factorize(SparseCholesky& solver, const Eigen::SparseMatrix<double>& a);

// Makes OpenBLAS, when it is the BLAS this process runs on, do its work on the calling thread;
// called once at the start of the programs (app/main.cpp, bench/main.cpp). Its threads wait for
// work by spinning, and on a busy machine every BLAS call then waits for a descheduled thread: the
// README's saddle took 108 s instead of 16 s beside two busy processes on 2 cores. On an idle
// machine they saved nothing (the paper's hat 12.0 s with them, 11.8 s without).
void use_single_threaded_blas();

}  // namespace flatmorph

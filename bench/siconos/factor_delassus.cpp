// factor_delassus — what one step of a direct (Newton-type) contact solver costs at least on
// an exported step: the sparse factorization of the Delassus matrix W = H (Δt M⁻¹) Hᵀ (3
// rows per contact, docs/lab/2026-11-25-siconos-newton-solvers.md).
// A semismooth Newton step (Alart–Curnier, Fischer–Burmeister) solves a linear system with
// W's sparsity pattern; a symmetric positive definite factorization of W + εI is the
// cheapest direct factorization of that pattern, so its time bounds one Newton iteration
// from below. Times the numeric factorization (the pattern analysed once) and one solve.
// Not part of the build (it needs CHOLMOD, libsuitesparse-dev):
//   /usr/bin/python3 bench/siconos/solve_steps.py delassus /tmp/front/step_0.json /tmp/W.mtx
//   g++ -O2 -march=native -I/usr/include/eigen3 -I/usr/include/suitesparse \
//       bench/siconos/factor_delassus.cpp -o /tmp/factor_delassus -lcholmod
//   OPENBLAS_NUM_THREADS=1 /tmp/factor_delassus /tmp/W.mtx
#include <Eigen/CholmodSupport>
#include <Eigen/Sparse>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <unsupported/Eigen/SparseExtra>
#include <vector>

namespace {

using SparseMatrix = Eigen::SparseMatrix<double>;

/// Median wall time of `repeat` calls [ms].
template <typename Work>
double median_ms(Work work, int repeat = 9) {
  std::vector<double> ms;
  for (int k = 0; k < repeat; ++k) {
    const auto start = std::chrono::steady_clock::now();
    work();
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                     .count());
  }
  std::sort(ms.begin(), ms.end());
  return ms[ms.size() / 2];
}

template <typename Factorization>
void time_factorization(const char* name, const SparseMatrix& A) {
  Factorization f;
  f.analyzePattern(A);
  const double factor = median_ms([&] { f.factorize(A); });
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(A.rows());
  Eigen::VectorXd x;
  const double solve = median_ms([&] { x = f.solve(b); });
  std::printf("%-28s factorize %7.2f ms  solve %6.3f ms\n", name, factor, solve);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: factor_delassus W.mtx\n");
    return 2;
  }
  SparseMatrix W;
  if (!Eigen::loadMarket(W, argv[1])) {
    std::fprintf(stderr, "factor_delassus: cannot read %s\n", argv[1]);
    return 2;
  }
  SparseMatrix identity(W.rows(), W.cols());
  identity.setIdentity();
  // W is scaled to a unit mean diagonal by the exporter; ε keeps rank-deficient W (a sphere
  // with more than six contacts, the piston's many contacts) factorizable
  const SparseMatrix A = W + 1e-6 * identity;
  std::printf("W: %ld rows (3 per contact), %ld non-zeros\n", static_cast<long>(A.rows()),
              static_cast<long>(A.nonZeros()));
  time_factorization<Eigen::SimplicialLDLT<SparseMatrix>>("Eigen SimplicialLDLT (AMD)", A);
  time_factorization<Eigen::CholmodSimplicialLDLT<SparseMatrix>>("CHOLMOD simplicial LDLT", A);
  time_factorization<Eigen::CholmodSupernodalLLT<SparseMatrix>>("CHOLMOD supernodal LLT", A);
  return 0;
}

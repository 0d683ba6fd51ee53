#include "fem/cholmod_factor.hpp"

#include <cholmod.h>

#include <cstring>
#include <limits>
#include <stdexcept>

namespace codesign::fem {

struct CholmodFactor::Impl {
  cholmod_common c;
  cholmod_sparse* A = nullptr;
  cholmod_factor* L = nullptr;
  cholmod_dense* B = nullptr;
  cholmod_dense* X = nullptr;
  cholmod_dense* Y = nullptr;
  cholmod_dense* E = nullptr;
  bool ok = false;
  int n = 0;

  Impl() {
    cholmod_start(&c);
    c.print = 0;
    c.error_handler = nullptr;  // report through status, never print or abort
    // Simplicial LDLᵀ: for the few-thousand-DOF systems here it beats the supernodal (BLAS-3)
    // path with Debian's reference BLAS, and its solves are cheaper.
    c.supernodal = CHOLMOD_SIMPLICIAL;
  }
  ~Impl() {
    if (B) cholmod_free_dense(&B, &c);
    if (X) cholmod_free_dense(&X, &c);
    if (Y) cholmod_free_dense(&Y, &c);
    if (E) cholmod_free_dense(&E, &c);
    if (L) cholmod_free_factor(&L, &c);
    if (A) cholmod_free_sparse(&A, &c);
    cholmod_finish(&c);
  }
};

CholmodFactor::CholmodFactor() : impl_(std::make_unique<Impl>()) {}
CholmodFactor::~CholmodFactor() = default;

void CholmodFactor::analyse(int n, const std::vector<int>& colptr, const std::vector<int>& rowind) {
  Impl& m = *impl_;
  if (m.L) cholmod_free_factor(&m.L, &m.c);
  if (m.A) cholmod_free_sparse(&m.A, &m.c);
  if (m.B) cholmod_free_dense(&m.B, &m.c);
  m.n = n;
  m.ok = false;
  const std::size_t nnz = rowind.size();
  m.A = cholmod_allocate_sparse(n, n, nnz, 1, 1, 1, CHOLMOD_REAL, &m.c);
  if (!m.A) throw std::runtime_error("CHOLMOD: cannot allocate the system matrix");
  std::memcpy(m.A->p, colptr.data(), sizeof(int) * (n + 1));
  std::memcpy(m.A->i, rowind.data(), sizeof(int) * nnz);
  std::memset(m.A->x, 0, sizeof(double) * nnz);
  m.L = cholmod_analyze(m.A, &m.c);
  if (!m.L) throw std::runtime_error("CHOLMOD: symbolic analysis failed");
  m.B = cholmod_allocate_dense(n, 1, n, CHOLMOD_REAL, &m.c);
}

bool CholmodFactor::factorise(const std::vector<double>& values) {
  Impl& m = *impl_;
  if (!m.A || values.size() != m.A->nzmax) return false;
  std::memcpy(m.A->x, values.data(), sizeof(double) * values.size());
  const int ok = cholmod_factorize(m.A, m.L, &m.c);
  m.ok = ok && m.c.status == CHOLMOD_OK && static_cast<int>(m.L->minor) >= m.n;
  return m.ok;
}

bool CholmodFactor::factorised() const { return impl_->ok; }
int CholmodFactor::size() const { return impl_->n; }

void CholmodFactor::solve(const double* b, double* x) {
  Impl& m = *impl_;
  std::memcpy(m.B->x, b, sizeof(double) * m.n);
  cholmod_solve2(CHOLMOD_A, m.L, m.B, nullptr, &m.X, nullptr, &m.Y, &m.E, &m.c);
  std::memcpy(x, m.X->x, sizeof(double) * m.n);
}

void CholmodFactor::solve(const Eigen::MatrixXd& Bm, Eigen::MatrixXd& Xm) {
  Impl& m = *impl_;
  const int k = static_cast<int>(Bm.cols());
  Xm.resize(m.n, k);
  if (k == 0) return;
  cholmod_dense* B = cholmod_allocate_dense(m.n, k, m.n, CHOLMOD_REAL, &m.c);
  std::memcpy(B->x, Bm.data(), sizeof(double) * m.n * k);
  cholmod_dense* X = cholmod_solve(CHOLMOD_A, m.L, B, &m.c);
  if (X) std::memcpy(Xm.data(), X->x, sizeof(double) * m.n * k);
  else Xm.setConstant(std::numeric_limits<double>::quiet_NaN());
  cholmod_free_dense(&X, &m.c);
  cholmod_free_dense(&B, &m.c);
}

long CholmodFactor::factor_nonzeros() const {
  const cholmod_factor* L = impl_->L;
  if (!L) return 0;
  if (L->is_super) return static_cast<long>(L->xsize);
  return static_cast<long>(L->nzmax);
}

}  // namespace codesign::fem

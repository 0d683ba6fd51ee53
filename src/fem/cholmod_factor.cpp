#include "fem/cholmod_factor.hpp"

#include <cholmod.h>

#include <algorithm>
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
  bool nodal = false;  // analysed with node-blocked AMD (dofs_per_node = 3)
  // The factor L D Lᵀ = P A Pᵀ in 3×3 blocks (when `blocked`): per block column K, the unit
  // lower triangle of its diagonal block (l10, l20, l21), 1/D of its three pivots, and its
  // off-diagonal blocks (first row of the block, values row-major).
  bool blocked = false;
  long nonzeros = 0;                // of the last factorisation's L
  std::vector<int> perm;            // perm[k]: original index of pivot k
  std::vector<double> diag_l;       // 3 per block column
  std::vector<double> inv_d;        // 1 per unknown
  std::vector<int> block_ptr;       // per block column, into block_row
  std::vector<int> block_row;       // 3 × block row index
  std::vector<double> block_val;    // 9 per block
  std::vector<double> work;

  void build_blocks();
  void block_solve(const double* b, double* x);

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

void CholmodFactor::clear() { impl_ = std::make_unique<Impl>(); }

void CholmodFactor::analyse(int n, const std::vector<int>& colptr, const std::vector<int>& rowind,
                            int dofs_per_node) {
  Impl& m = *impl_;
  if (m.L) cholmod_free_factor(&m.L, &m.c);
  if (m.A) cholmod_free_sparse(&m.A, &m.c);
  if (m.B) cholmod_free_dense(&m.B, &m.c);
  m.n = n;
  m.ok = false;
  const std::size_t nnz = rowind.size();
  // The pattern only: factorise() lends CHOLMOD the caller's values for the one call, so a
  // stored factor carries no copy of its matrix.
  m.A = cholmod_allocate_sparse(n, n, nnz, 1, 1, 1, CHOLMOD_PATTERN, &m.c);
  if (!m.A) throw std::runtime_error("CHOLMOD: cannot allocate the system matrix");
  std::memcpy(m.A->p, colptr.data(), sizeof(int) * (n + 1));
  std::memcpy(m.A->i, rowind.data(), sizeof(int) * nnz);
  m.nodal = dofs_per_node == 3 && n % 3 == 0 && n > 0;
  m.blocked = false;
  if (m.nodal) {
    // The node graph (upper triangle, pattern only), ordered by AMD; pivots follow node by node.
    const int nn = n / 3;
    std::vector<std::vector<int>> cols(nn);
    for (int j = 0; j < n; ++j)
      for (int p = colptr[j]; p < colptr[j + 1]; ++p) cols[j / 3].push_back(rowind[p] / 3);
    std::size_t nnz_nodes = 0;
    for (auto& c : cols) {
      std::sort(c.begin(), c.end());
      c.erase(std::unique(c.begin(), c.end()), c.end());
      nnz_nodes += c.size();
    }
    cholmod_sparse* G = cholmod_allocate_sparse(nn, nn, nnz_nodes, 1, 1, 1, CHOLMOD_PATTERN, &m.c);
    if (!G) throw std::runtime_error("CHOLMOD: cannot allocate the node graph");
    int* gp = static_cast<int*>(G->p);
    int* gi = static_cast<int*>(G->i);
    gp[0] = 0;
    for (int k = 0; k < nn; ++k) {
      std::copy(cols[k].begin(), cols[k].end(), gi + gp[k]);
      gp[k + 1] = gp[k] + static_cast<int>(cols[k].size());
    }
    std::vector<int> node_perm(nn), dof_perm(n);
    const int ok = cholmod_amd(G, nullptr, 0, node_perm.data(), &m.c);
    cholmod_free_sparse(&G, &m.c);
    if (!ok) throw std::runtime_error("CHOLMOD: AMD ordering of the node graph failed");
    for (int k = 0; k < nn; ++k)
      for (int c = 0; c < 3; ++c) dof_perm[3 * k + c] = 3 * node_perm[k] + c;
    m.c.nmethods = 1;
    m.c.method[0].ordering = CHOLMOD_GIVEN;
    m.c.postorder = 0;  // keep each node's pivots together
    m.L = cholmod_analyze_p(m.A, dof_perm.data(), nullptr, 0, &m.c);
  } else {
    m.L = cholmod_analyze(m.A, &m.c);
  }
  if (!m.L) throw std::runtime_error("CHOLMOD: symbolic analysis failed");
  m.B = cholmod_allocate_dense(n, 1, n, CHOLMOD_REAL, &m.c);
}

bool CholmodFactor::factorise(const std::vector<double>& values) {
  Impl& m = *impl_;
  if (!m.A || values.size() != m.A->nzmax) return false;
  // cholmod_factorize only reads A.
  m.A->x = const_cast<double*>(values.data());
  m.A->xtype = CHOLMOD_REAL;
  const int ok = cholmod_factorize(m.A, m.L, &m.c);
  m.A->x = nullptr;
  m.A->xtype = CHOLMOD_PATTERN;
  m.ok = ok && m.c.status == CHOLMOD_OK && static_cast<int>(m.L->minor) >= m.n;
  if (m.ok && !m.L->is_super && !m.L->is_ll) {
    // A simplicial LDLᵀ factorisation succeeds on an indefinite matrix too (with negative
    // pivots); positive definite means every pivot D_jj > 0 (the first entry of column j).
    const int* Lp = static_cast<const int*>(m.L->p);
    const double* Lx = static_cast<const double*>(m.L->x);
    for (int j = 0; j < m.n && m.ok; ++j) m.ok = Lx[Lp[j]] > 0.0;
  }
  m.blocked = false;
  m.nonzeros = m.ok ? static_cast<long>(m.L->is_super ? m.L->xsize : m.L->nzmax) : 0;
  if (m.ok && m.nodal) m.build_blocks();
  // Once the block copy holds the factor, CHOLMOD's own copy is dead weight until the next
  // factorisation: turn it back into the symbolic factor (ordering and column counts), about
  // half of what a stored factor costs. The next factorise() computes the same values into it.
  if (m.blocked) cholmod_change_factor(CHOLMOD_PATTERN, false, false, true, true, m.L, &m.c);
  return m.ok;
}

bool CholmodFactor::factorised() const { return impl_->ok; }
int CholmodFactor::size() const { return impl_->n; }

void CholmodFactor::Impl::build_blocks() {
  blocked = false;
  if (L->is_super || L->is_ll || L->xtype != CHOLMOD_REAL) return;
  const int* Lp = static_cast<const int*>(L->p);
  const int* Li = static_cast<const int*>(L->i);
  const int* Lnz = static_cast<const int*>(L->nz);
  const double* Lx = static_cast<const double*>(L->x);
  const int* P = static_cast<const int*>(L->Perm);
  const int nb = n / 3;
  perm.assign(P, P + n);
  diag_l.resize(3 * nb);
  inv_d.resize(n);
  block_ptr.assign(nb + 1, 0);
  block_row.clear();
  block_val.clear();
  work.resize(n);
  for (int K = 0; K < nb; ++K) {
    const int j0 = 3 * K;
    // Column j0 + c starts with its pivot, then the rows j0 + c + 1 .. j0 + 2 of the diagonal
    // block, then the off-diagonal rows, in triples 3I, 3I + 1, 3I + 2, the same in all three.
    const int m0 = Lnz[j0] - 3;
    if (m0 < 0 || m0 % 3 != 0 || Lnz[j0 + 1] - 2 != m0 || Lnz[j0 + 2] - 1 != m0) return;
    for (int c = 0; c < 3; ++c) {
      const int p = Lp[j0 + c];
      for (int r = 0; r <= 2 - c; ++r)
        if (Li[p + r] != j0 + c + r) return;
      inv_d[j0 + c] = 1.0 / Lx[p];
    }
    diag_l[3 * K + 0] = Lx[Lp[j0] + 1];
    diag_l[3 * K + 1] = Lx[Lp[j0] + 2];
    diag_l[3 * K + 2] = Lx[Lp[j0 + 1] + 1];
    const int blocks = m0 / 3;
    for (int t = 0; t < blocks; ++t) {
      const int row = Li[Lp[j0] + 3 + 3 * t];
      if (row % 3 != 0 || row <= j0 + 2) return;
      for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r)
          if (Li[Lp[j0 + c] + (3 - c) + 3 * t + r] != row + r) return;
      block_row.push_back(row);
      double v[9];
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) v[3 * r + c] = Lx[Lp[j0 + c] + (3 - c) + 3 * t + r];
      block_val.insert(block_val.end(), v, v + 9);
    }
    block_ptr[K + 1] = static_cast<int>(block_row.size());
  }
  blocked = true;
}

void CholmodFactor::Impl::block_solve(const double* b, double* x) {
  // A = Pᵀ L D Lᵀ P: y = P b, y ← L⁻¹ y, y ← D⁻¹ y, y ← L⁻ᵀ y, x = Pᵀ y.
  double* y = work.data();
  for (int k = 0; k < n; ++k) y[k] = b[perm[k]];
  const int nb = n / 3;
  const int* row = block_row.data();
  const double* val = block_val.data();
  for (int K = 0; K < nb; ++K) {
    const double* dl = &diag_l[3 * K];
    const double y0 = y[3 * K];
    const double y1 = y[3 * K + 1] - dl[0] * y0;
    const double y2 = y[3 * K + 2] - dl[1] * y0 - dl[2] * y1;
    y[3 * K + 1] = y1;
    y[3 * K + 2] = y2;
    for (int t = block_ptr[K]; t < block_ptr[K + 1]; ++t) {
      double* yi = y + row[t];
      const double* v = val + 9 * t;
      yi[0] -= v[0] * y0 + v[1] * y1 + v[2] * y2;
      yi[1] -= v[3] * y0 + v[4] * y1 + v[5] * y2;
      yi[2] -= v[6] * y0 + v[7] * y1 + v[8] * y2;
    }
  }
  for (int k = 0; k < n; ++k) y[k] *= inv_d[k];
  for (int K = nb - 1; K >= 0; --K) {
    double x0 = y[3 * K], x1 = y[3 * K + 1], x2 = y[3 * K + 2];
    for (int t = block_ptr[K]; t < block_ptr[K + 1]; ++t) {
      const double* yi = y + row[t];
      const double* v = val + 9 * t;
      x0 -= v[0] * yi[0] + v[3] * yi[1] + v[6] * yi[2];
      x1 -= v[1] * yi[0] + v[4] * yi[1] + v[7] * yi[2];
      x2 -= v[2] * yi[0] + v[5] * yi[1] + v[8] * yi[2];
    }
    const double* dl = &diag_l[3 * K];
    x1 -= dl[2] * x2;
    x0 -= dl[0] * x1 + dl[1] * x2;
    y[3 * K] = x0;
    y[3 * K + 1] = x1;
    y[3 * K + 2] = x2;
  }
  for (int k = 0; k < n; ++k) x[perm[k]] = y[k];
}

void CholmodFactor::solve(const double* b, double* x) {
  Impl& m = *impl_;
  if (m.blocked) {
    m.block_solve(b, x);
    return;
  }
  std::memcpy(m.B->x, b, sizeof(double) * m.n);
  cholmod_solve2(CHOLMOD_A, m.L, m.B, nullptr, &m.X, nullptr, &m.Y, &m.E, &m.c);
  std::memcpy(x, m.X->x, sizeof(double) * m.n);
}

void CholmodFactor::solve(const Eigen::MatrixXd& Bm, Eigen::MatrixXd& Xm) {
  Impl& m = *impl_;
  const int k = static_cast<int>(Bm.cols());
  Xm.resize(m.n, k);
  if (k == 0) return;
  if (m.blocked) {
    for (int c = 0; c < k; ++c) m.block_solve(Bm.col(c).data(), Xm.col(c).data());
    return;
  }
  cholmod_dense* B = cholmod_allocate_dense(m.n, k, m.n, CHOLMOD_REAL, &m.c);
  std::memcpy(B->x, Bm.data(), sizeof(double) * m.n * k);
  cholmod_dense* X = cholmod_solve(CHOLMOD_A, m.L, B, &m.c);
  if (X) std::memcpy(Xm.data(), X->x, sizeof(double) * m.n * k);
  else Xm.setConstant(std::numeric_limits<double>::quiet_NaN());
  cholmod_free_dense(&X, &m.c);
  cholmod_free_dense(&B, &m.c);
}

bool CholmodFactor::block_solves() const { return impl_->ok && impl_->blocked; }

long CholmodFactor::factor_nonzeros() const { return impl_->ok ? impl_->nonzeros : 0; }

}  // namespace codesign::fem

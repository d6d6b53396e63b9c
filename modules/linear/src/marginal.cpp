#include <swba/linear/marginal.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace swba
{
namespace
{
/** H(rows, cols) in the listed orders. */
Eigen::MatrixXd gather(const Eigen::MatrixXd& H, const std::vector<int>& rows, const std::vector<int>& cols)
{
	const Eigen::Index nr = static_cast<Eigen::Index>(rows.size()), nc = static_cast<Eigen::Index>(cols.size());
	Eigen::MatrixXd out(nr, nc);
	for (Eigen::Index j = 0; j < nc; j++)
		for (Eigen::Index i = 0; i < nr; i++) out(i, j) = H(rows[i], cols[j]);
	return out;
}

Eigen::VectorXd gather(const Eigen::VectorXd& b, const std::vector<int>& idx)
{
	Eigen::VectorXd out(static_cast<Eigen::Index>(idx.size()));
	for (std::size_t i = 0; i < idx.size(); i++) out[static_cast<Eigen::Index>(i)] = b[idx[i]];
	return out;
}

/** Columns `cols` of J, in that order. */
Eigen::MatrixXd gather_columns(const Eigen::MatrixXd& J, const std::vector<int>& cols)
{
	Eigen::MatrixXd out(J.rows(), static_cast<Eigen::Index>(cols.size()));
	for (std::size_t c = 0; c < cols.size(); c++) out.col(static_cast<Eigen::Index>(c)) = J.col(cols[c]);
	return out;
}

/** AᵀA through a symmetric rank update of the lower triangle, mirrored. */
Eigen::MatrixXd gram(const Eigen::MatrixXd& A)
{
	Eigen::MatrixXd G = Eigen::MatrixXd::Zero(A.cols(), A.cols());
	if (A.rows() == 0 || A.cols() == 0) return G;  // (Eigen's blocking divides by the depth)
	G.selfadjointView<Eigen::Lower>().rankUpdate(A.transpose());
	return Eigen::MatrixXd(G.selfadjointView<Eigen::Lower>());
}

/** Cholesky factor with diagonal pivoting on the updated diagonal (LAPACK's dpstrf scheme): Pᵀ H P =
 * L Lᵀ + S, stopped as soon as the largest remaining diagonal of the Schur complement S is not above
 * rel_threshold times the first (largest) pivot. H being semi-definite, its diagonal bounds S, so S
 * is numerically zero: the factor is rank-revealing, unlike a pivoted LDLᵀ that chooses its pivots
 * on the original diagonal (Eigen::LDLT), whose pivots after a tiny one are ratios of rounding noise.
 * `scale` (if larger) replaces the first pivot as the reference: the magnitude of the system H came
 * from, so that an H that is all rounding noise (a Schur complement that cancels) has rank 0. */
struct PivotedCholesky
{
	Eigen::MatrixXd L;      ///< n × rank, lower trapezoidal (rows in pivot order)
	std::vector<int> perm;  ///< row i of L is coordinate perm[i] of H
	int rank = 0;
};

PivotedCholesky pivoted_cholesky(const Eigen::MatrixXd& H, double rel_threshold, double scale)
{
	const Eigen::Index n = H.rows();
	PivotedCholesky c;
	Eigen::MatrixXd A = H;  // rows/columns swapped along with perm; only its lower triangle is read
	c.perm.resize(static_cast<std::size_t>(n));
	for (Eigen::Index i = 0; i < n; i++) c.perm[static_cast<std::size_t>(i)] = static_cast<int>(i);
	c.L.setZero(n, n);
	Eigen::VectorXd d = A.diagonal();  // diagonal of the current Schur complement
	double first = 0;
	for (Eigen::Index k = 0; k < n; k++)
	{
		Eigen::Index j;
		const double dj = d.tail(n - k).maxCoeff(&j);
		j += k;
		if (k == 0) first = std::max(dj, scale);
		if (!(dj > 0) || !(dj > rel_threshold * first)) break;
		if (j != k)
		{
			A.row(k).swap(A.row(j));
			A.col(k).swap(A.col(j));
			c.L.row(k).swap(c.L.row(j));
			std::swap(d[k], d[j]);
			std::swap(c.perm[static_cast<std::size_t>(k)], c.perm[static_cast<std::size_t>(j)]);
		}
		const double lkk = std::sqrt(dj);
		c.L(k, k) = lkk;
		const Eigen::Index rest = n - k - 1;
		if (rest > 0)
		{
			// Left-looking column: L(k+1:, k) = (A(k+1:, k) − L(k+1:, :k) L(k, :k)ᵀ) / L(k, k).
			c.L.col(k).tail(rest) = A.col(k).tail(rest);
			c.L.col(k).tail(rest).noalias() -= c.L.bottomLeftCorner(rest, k) * c.L.row(k).head(k).transpose();
			c.L.col(k).tail(rest) /= lkk;
			d.tail(rest) -= c.L.col(k).tail(rest).cwiseAbs2();
		}
		c.rank = static_cast<int>(k) + 1;
	}
	c.L.conservativeResize(n, c.rank);
	return c;
}

/** Throws unless `keep` and `marg` are disjoint, unrepeated indices into [0, n). */
void check_index_sets(int n, const std::vector<int>& keep, const std::vector<int>& marg)
{
	std::vector<char> used(n, 0);
	for (const auto* set : {&keep, &marg})
		for (int i : *set)
		{
			if (i < 0 || i >= n || used[i]) throw std::invalid_argument("marginalize: bad or repeated index");
			used[i] = 1;
		}
}
}  // namespace

Eigen::MatrixXd truncated_pseudo_inverse(const Eigen::MatrixXd& H, double rel_threshold)
{
	const Eigen::Index n = H.rows();
	Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(0.5 * (H + H.transpose()));
	const Eigen::VectorXd& ev = es.eigenvalues();
	const double lmax = ev.size() ? std::max(ev.maxCoeff(), 0.0) : 0.0;
	Eigen::VectorXd inv = Eigen::VectorXd::Zero(n);
	for (Eigen::Index i = 0; i < n; i++)
		if (ev[i] > rel_threshold * lmax && ev[i] > 0) inv[i] = 1.0 / ev[i];
	return es.eigenvectors() * inv.asDiagonal() * es.eigenvectors().transpose();
}

MarginalizationResult marginalize(const Eigen::MatrixXd& H, const Eigen::VectorXd& b,
								  const std::vector<int>& keep, const std::vector<int>& marg,
								  double rel_threshold)
{
	const int n = static_cast<int>(H.rows());
	if (H.cols() != n || b.size() != n) throw std::invalid_argument("marginalize: H must be n×n and b n");
	check_index_sets(n, keep, marg);
	return eliminate(partition_normal_equations(H, b, marg, keep), rel_threshold).marginal;
}

void square_root_form(MarginalizationResult& m, double rel_threshold, double scale)
{
	const int n = static_cast<int>(m.H.rows());
	if (m.H.cols() != n || m.b.size() != n) throw std::invalid_argument("square_root_form: H must be n×n and b n");
	const PivotedCholesky c = pivoted_cholesky(m.H, rel_threshold, scale);
	m.rank = c.rank;
	// Pᵀ H* P ≈ L Lᵀ over the leading `rank` columns of L: J = Lᵀ Pᵀ (column perm[i] of J is row i of L)
	// and Jᵀe = −b* on the kept coordinates, e = −L₁₁⁻¹ (Pᵀ b*)₁.
	m.J.setZero(c.rank, n);
	Eigen::VectorXd pb(c.rank);
	if (c.rank > 0)  // (a row of an n×0 L would offset its null data pointer)
		for (int i = 0; i < n; i++) m.J.col(c.perm[i]) = c.L.row(i).head(c.rank).transpose();
	for (int i = 0; i < c.rank; i++) pb[i] = m.b[c.perm[i]];
	m.e = -(c.L.topLeftCorner(c.rank, c.rank).triangularView<Eigen::Lower>().solve(pb));
	// The prior is the truncated quadratic ½‖e + J δ‖²: H and b are replaced by JᵀJ and −Jᵀe, so every
	// form of the result describes the same cost (the untruncated H* differs from it by the dropped,
	// numerically zero block, which need not be semi-definite).
	if (c.rank < n)
	{
		m.H = gram(m.J);
		m.b = -(m.J.transpose() * m.e);
	}
}

MarginalizationResult marginalize_leading(const Eigen::MatrixXd& H, const Eigen::VectorXd& b, int num_keep,
										  double threshold, double scale)
{
	return eliminate(partition_leading(H, b, num_keep), threshold, false, scale).marginal;
}

PartitionedNormalEquations partition_normal_equations(const Eigen::MatrixXd& H, const Eigen::VectorXd& b,
													  const std::vector<int>& p, const std::vector<int>& a)
{
	if (H.rows() != H.cols() || b.size() != H.rows())
		throw std::invalid_argument("partition_normal_equations: H and b disagree");
	return {gather(H, p, p), gather(H, p, a), gather(H, a, a), gather(b, p), gather(b, a)};
}

PartitionedNormalEquations partition_square_root(const Eigen::MatrixXd& J, const Eigen::VectorXd& e,
												 const std::vector<int>& p, const std::vector<int>& a)
{
	if (e.size() != J.rows()) throw std::invalid_argument("partition_square_root: J and e disagree");
	const Eigen::MatrixXd Jp = gather_columns(J, p), Ja = gather_columns(J, a);
	PartitionedNormalEquations s;
	s.Hpp = gram(Jp);
	s.Haa = gram(Ja);
	s.Hpa = Jp.transpose() * Ja;
	s.bp = -(Jp.transpose() * e);
	s.ba = -(Ja.transpose() * e);
	return s;
}

PartitionedNormalEquations partition_leading(const Eigen::MatrixXd& H, const Eigen::VectorXd& b, int num_keep)
{
	const int n = static_cast<int>(H.rows());
	if (H.cols() != n || b.size() != n || num_keep < 0 || num_keep > n)
		throw std::invalid_argument("partition_leading: H must be n×n, b n, 0 <= num_keep <= n");
	const int nk = num_keep, nm = n - num_keep;
	return {H.bottomRightCorner(nm, nm), H.bottomLeftCorner(nm, nk), H.topLeftCorner(nk, nk), b.tail(nm), b.head(nk)};
}

SymmetricInverse::SymmetricInverse(const Eigen::MatrixXd& A, double rel_threshold) : llt_(A)
{
	const Eigen::VectorXd piv = llt_.matrixLLT().diagonal().cwiseAbs2();
	const double pmax = piv.size() ? piv.maxCoeff() : 0.0;
	cholesky_ = llt_.info() == Eigen::Success && pmax > 0 && piv.minCoeff() > rel_threshold * pmax;
	if (!cholesky_ && A.rows() > 0) pseudo_inverse_ = truncated_pseudo_inverse(A, rel_threshold);
}

Eigen::MatrixXd SymmetricInverse::solve(const Eigen::MatrixXd& B) const
{
	if (cholesky_) return llt_.solve(B);
	if (pseudo_inverse_.size() == 0) return Eigen::MatrixXd::Zero(0, B.cols());
	return pseudo_inverse_ * B;
}

Eigen::MatrixXd SymmetricInverse::inverse() const
{
	return cholesky_ ? Eigen::MatrixXd(llt_.solve(Eigen::MatrixXd::Identity(llt_.rows(), llt_.cols())))
					 : pseudo_inverse_;
}

namespace
{
/** m.J, m.e, m.rank from m.H, m.b: a blocked Cholesky when m.H is clearly positive definite, else
 * square_root_form (see GaussianElimination::marginal). */
void leading_square_root(MarginalizationResult& m, double threshold, double scale)
{
	Eigen::LLT<Eigen::MatrixXd> llt(m.H);
	if (llt.info() != Eigen::Success) return square_root_form(m, threshold, scale);
	const Eigen::VectorXd piv = llt.matrixLLT().diagonal().cwiseAbs2();
	if (!(piv.minCoeff() > threshold * std::max(piv.maxCoeff(), scale))) return square_root_form(m, threshold, scale);
	// ½‖e + J δ‖² = ½ δᵀ H* δ − b*ᵀ δ + const with J = Lᵀ, Jᵀe = −b*: e = −L⁻¹ b*.
	m.J = llt.matrixU();
	m.e = -(llt.matrixL().solve(m.b));
	m.rank = static_cast<int>(m.H.rows());
}
}  // namespace

GaussianElimination eliminate(PartitionedNormalEquations s, double threshold, bool with_covariance, double scale)
{
	GaussianElimination out;
	const Eigen::Index na = s.Haa.rows();
	if (na > 0) scale = std::max(scale, s.Haa.diagonal().maxCoeff());
	if (s.Hpp.rows() > 0)
	{
		const SymmetricInverse inverse(s.Hpp, threshold);
		out.conditional.K = inverse.solve(s.Hpa);
		out.conditional.k = inverse.solve(s.bp);
		if (with_covariance) out.conditional.covariance = inverse.inverse();
		s.Haa.noalias() -= s.Hpa.transpose() * out.conditional.K;
		s.ba.noalias() -= s.Hpa.transpose() * out.conditional.k;
	}
	if (na == 0) return out;
	out.marginal.H = 0.5 * (s.Haa + s.Haa.transpose());
	out.marginal.b = std::move(s.ba);
	leading_square_root(out.marginal, threshold, scale);
	return out;
}
}  // namespace swba

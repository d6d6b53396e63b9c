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
	const Eigen::MatrixXd Hkk = gather(H, keep, keep), Hkm = gather(H, keep, marg), Hmm = gather(H, marg, marg);
	const Eigen::VectorXd bk = gather(b, keep), bm = gather(b, marg);
	MarginalizationResult out;
	if (!marg.empty())
	{
		const Eigen::MatrixXd Hmm_inv = truncated_pseudo_inverse(Hmm, rel_threshold);
		const Eigen::MatrixXd K = Hkm * Hmm_inv;
		out.H = Hkk - K * Hkm.transpose();
		out.b = bk - K * bm;
	}
	else
	{
		out.H = Hkk;
		out.b = bk;
	}
	out.H = 0.5 * (out.H + out.H.transpose()).eval();

	square_root_form(out, rel_threshold, Hkk.size() ? Hkk.diagonal().maxCoeff() : 0.0);
	return out;
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
	const int n = static_cast<int>(H.rows());
	if (H.cols() != n || b.size() != n || num_keep < 0 || num_keep > n)
		throw std::invalid_argument("marginalize_leading: H must be n×n, b n, 0 <= num_keep <= n");
	const int nk = num_keep, nm = n - num_keep;
	if (nk > 0) scale = std::max(scale, H.topLeftCorner(nk, nk).diagonal().maxCoeff());
	MarginalizationResult out;
	if (nm > 0)
	{
		const Eigen::MatrixXd Hmm_inv = truncated_pseudo_inverse(H.bottomRightCorner(nm, nm), threshold);
		const Eigen::MatrixXd K = H.topRightCorner(nk, nm) * Hmm_inv;
		out.H = H.topLeftCorner(nk, nk);
		out.H.noalias() -= K * H.topRightCorner(nk, nm).transpose();
		out.b = b.head(nk) - K * b.tail(nm);
	}
	else
	{
		out.H = H;
		out.b = b;
	}
	out.H = 0.5 * (out.H + out.H.transpose()).eval();
	// Square root: a blocked Cholesky when H* is well conditioned, else (rank-deficient H*, e.g. anchor
	// poses of inverse-depth landmarks or a free gauge, doc/window.md) the truncated pivoted Cholesky
	// of the same H*. Both cut relative to the kept block before elimination (`scale`).
	const auto pivoted_form = [&] {
		square_root_form(out, threshold, scale);
		return out;
	};
	if (nk == 0) return pivoted_form();
	Eigen::LLT<Eigen::MatrixXd> llt(out.H);
	if (llt.info() != Eigen::Success) return pivoted_form();
	const Eigen::VectorXd piv = llt.matrixLLT().diagonal().cwiseAbs2();
	if (!(piv.minCoeff() > threshold * std::max(piv.maxCoeff(), scale))) return pivoted_form();
	// ½‖e + J δ‖² = ½ δᵀ H* δ − b*ᵀ δ + const with J = Lᵀ, Jᵀe = −b*: e = −L⁻¹ b*.
	out.J = llt.matrixU();
	out.e = -(llt.matrixL().solve(out.b));
	out.rank = nk;
	return out;
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

ConditionalElimination eliminate_conditional(PartitionedNormalEquations s, double threshold)
{
	ConditionalElimination out;
	// K = Hpp⁻¹ Hpa, k = Hpp⁻¹ bp: blocked Cholesky when Hpp is clearly positive definite, else the
	// thresholded pseudo-inverse marginalize() uses.
	Eigen::LLT<Eigen::MatrixXd> llt(s.Hpp);
	const Eigen::VectorXd piv = llt.matrixLLT().diagonal().cwiseAbs2();
	const double pmax = piv.size() ? piv.maxCoeff() : 0.0;
	if (llt.info() == Eigen::Success && pmax > 0 && piv.minCoeff() > threshold * pmax)
	{
		out.K = llt.solve(s.Hpa);
		out.k = llt.solve(s.bp);
	}
	else
	{
		const Eigen::MatrixXd Hpp_inv = truncated_pseudo_inverse(s.Hpp, threshold);
		out.K = Hpp_inv * s.Hpa;
		out.k = Hpp_inv * s.bp;
	}
	const Eigen::Index na = s.Haa.rows();
	if (na == 0) return out;
	const double scale = s.Haa.diagonal().maxCoeff();
	s.Haa.noalias() -= s.Hpa.transpose() * out.K;
	const Eigen::VectorXd b_red = s.ba - s.Hpa.transpose() * out.k;
	out.marginal = marginalize_leading(s.Haa, b_red, static_cast<int>(na), threshold, scale);
	return out;
}
}  // namespace swba

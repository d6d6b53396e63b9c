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
	G.selfadjointView<Eigen::Lower>().rankUpdate(A.transpose());
	return Eigen::MatrixXd(G.selfadjointView<Eigen::Lower>());
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

	square_root_form(out, rel_threshold);
	return out;
}

void square_root_form(MarginalizationResult& m, double rel_threshold)
{
	const int n = static_cast<int>(m.H.rows());
	if (m.H.cols() != n || m.b.size() != n) throw std::invalid_argument("square_root_form: H must be n×n and b n");
	// Square-root form from a pivoted LDLᵀ (H* = Pᵀ L D Lᵀ P): J = √D Lᵀ P, e = −√D⁻¹ L⁻¹ P b*, keeping
	// the pivots above rel_threshold·max(D). An order of magnitude cheaper than an eigen-decomposition
	// on the dense landmark priors of a SLAM window, and the same prior where nothing is truncated.
	Eigen::LDLT<Eigen::MatrixXd> ldlt(m.H);
	const Eigen::VectorXd D = ldlt.vectorD();
	const double dmax = n ? std::max(D.maxCoeff(), 0.0) : 0.0;
	const Eigen::MatrixXd L = ldlt.matrixL();
	// Rows of Lᵀ P: (Lᵀ P)_i = (Pᵀ L)ᵀ_i.
	Eigen::MatrixXd PtL = L;
	PtL = ldlt.transpositionsP().transpose() * PtL;
	Eigen::VectorXd Pb = ldlt.transpositionsP() * m.b;
	const Eigen::VectorXd y = L.triangularView<Eigen::UnitLower>().solve(Pb);
	std::vector<int> kept;
	for (int i = 0; i < n; i++)
		if (D[i] > rel_threshold * dmax && D[i] > 0) kept.push_back(i);
	m.rank = static_cast<int>(kept.size());
	m.J.resize(m.rank, n);
	m.e.resize(m.rank);
	for (int r = 0; r < m.rank; r++)
	{
		const int i = kept[r];
		const double s = std::sqrt(D[i]);
		m.J.row(r) = s * PtL.col(i).transpose();
		m.e[r] = -y[i] / s;
	}
}

MarginalizationResult marginalize_leading(const Eigen::MatrixXd& H, const Eigen::VectorXd& b, int num_keep,
										  double threshold)
{
	const int n = static_cast<int>(H.rows());
	if (H.cols() != n || b.size() != n || num_keep < 0 || num_keep > n)
		throw std::invalid_argument("marginalize_leading: H must be n×n, b n, 0 <= num_keep <= n");
	const int nk = num_keep, nm = n - num_keep;
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
	// poses of inverse-depth landmarks, doc/window.md) the truncated pivoted LDLᵀ on the same H*.
	const auto ldlt_form = [&] {
		square_root_form(out, threshold);
		return out;
	};
	if (nk == 0) return ldlt_form();
	Eigen::LLT<Eigen::MatrixXd> llt(out.H);
	if (llt.info() != Eigen::Success) return ldlt_form();
	const Eigen::VectorXd piv = llt.matrixLLT().diagonal().cwiseAbs2();
	if (!(piv.minCoeff() > threshold * piv.maxCoeff())) return ldlt_form();
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
	s.Haa.noalias() -= s.Hpa.transpose() * out.K;
	const Eigen::VectorXd b_red = s.ba - s.Hpa.transpose() * out.k;
	out.marginal = marginalize_leading(s.Haa, b_red, static_cast<int>(na), threshold);
	return out;
}
}  // namespace swba

#include <swba/linear/marginal.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <stdexcept>

namespace swba
{
MarginalizationResult marginalize(const Eigen::MatrixXd& H, const Eigen::VectorXd& b,
								  const std::vector<int>& keep, const std::vector<int>& marg,
								  double rel_threshold)
{
	const int n = static_cast<int>(H.rows());
	if (H.cols() != n || b.size() != n) throw std::invalid_argument("marginalize: H must be n×n and b n");
	std::vector<char> used(n, 0);
	for (int i : keep)
	{
		if (i < 0 || i >= n || used[i]) throw std::invalid_argument("marginalize: bad or repeated index");
		used[i] = 1;
	}
	for (int i : marg)
	{
		if (i < 0 || i >= n || used[i]) throw std::invalid_argument("marginalize: bad or repeated index");
		used[i] = 1;
	}
	const int nk = static_cast<int>(keep.size()), nm = static_cast<int>(marg.size());
	Eigen::MatrixXd Hkk(nk, nk), Hkm(nk, nm), Hmm(nm, nm);
	Eigen::VectorXd bk(nk), bm(nm);
	for (int i = 0; i < nk; i++)
	{
		bk[i] = b[keep[i]];
		for (int j = 0; j < nk; j++) Hkk(i, j) = H(keep[i], keep[j]);
		for (int j = 0; j < nm; j++) Hkm(i, j) = H(keep[i], marg[j]);
	}
	for (int i = 0; i < nm; i++)
	{
		bm[i] = b[marg[i]];
		for (int j = 0; j < nm; j++) Hmm(i, j) = H(marg[i], marg[j]);
	}
	MarginalizationResult out;
	if (nm > 0)
	{
		Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(0.5 * (Hmm + Hmm.transpose()));
		const Eigen::VectorXd& ev = es.eigenvalues();
		const double lmax = ev.size() ? std::max(ev.maxCoeff(), 0.0) : 0.0;
		Eigen::VectorXd inv = Eigen::VectorXd::Zero(nm);
		for (int i = 0; i < nm; i++)
			if (ev[i] > rel_threshold * lmax && ev[i] > 0) inv[i] = 1.0 / ev[i];
		const Eigen::MatrixXd Hmm_inv = es.eigenvectors() * inv.asDiagonal() * es.eigenvectors().transpose();
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
}  // namespace swba

// Pose-graph initialisation: odometry spanning tree and chordal relaxation (see pose_graph_init.h).
#include <swba/core/lie.h>
#include <swba/core/timing.h>
#include <swba/linear/block_cholesky.h>
#include <swba/problems/pose_graph_init.h>

#include "pose_graph_residual.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numeric>
#include <stdexcept>

namespace swba::problems
{
namespace
{
using io::G2oId;
using io::PoseGraph;

Eigen::Matrix2d rot2(double theta)
{
	const double c = std::cos(theta), s = std::sin(theta);
	return (Eigen::Matrix2d() << c, -s, s, c).finished();
}

class UnionFind
{
   public:
	explicit UnionFind(int n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }
	int find(int v)
	{
		while (parent_[v] != v) v = parent_[v] = parent_[parent_[v]];
		return v;
	}
	/** Returns false if a and b were already joined. The smaller root becomes the root (deterministic). */
	bool unite(int a, int b)
	{
		a = find(a), b = find(b);
		if (a == b) return false;
		if (b < a) std::swap(a, b);
		parent_[b] = a;
		return true;
	}

   private:
	std::vector<int> parent_;
};

/** Dense vertex indices (id order) and the edges as index pairs (file order). */
struct GraphIndex
{
	std::vector<G2oId> ids;
	std::map<G2oId, int> index;
	std::vector<std::pair<int, int>> edges;
};

GraphIndex index_graph(const PoseGraph& g)
{
	GraphIndex gi;
	const auto add = [&](G2oId id) {
		gi.index[id] = static_cast<int>(gi.ids.size());
		gi.ids.push_back(id);
	};
	for (const auto& kv : g.vertices3) add(kv.first);
	for (const auto& kv : g.vertices2) add(kv.first);
	for (const auto& e : g.edges3) gi.edges.emplace_back(gi.index.at(e.from), gi.index.at(e.to));
	for (const auto& e : g.edges2) gi.edges.emplace_back(gi.index.at(e.from), gi.index.at(e.to));
	return gi;
}

/** FIX vertices (else the lowest id), plus the lowest-id vertex of every component without one. */
std::vector<char> choose_anchors(const PoseGraph& g, const GraphIndex& gi, PoseGraphInitSummary& s)
{
	const int n = static_cast<int>(gi.ids.size());
	std::vector<char> anchored(n, 0);
	if (g.fixed.empty()) anchored[0] = 1;
	for (G2oId id : g.fixed) anchored[gi.index.at(id)] = 1;
	UnionFind uf(n);
	for (const auto& [a, b] : gi.edges) uf.unite(a, b);
	std::vector<char> root_anchored(n, 0);
	for (int v = 0; v < n; v++)
		if (anchored[v]) root_anchored[uf.find(v)] = 1;
	for (int v = 0; v < n; v++)
	{
		const int r = uf.find(v);
		if (r == v) s.num_components++;
		if (!root_anchored[r])
		{
			root_anchored[r] = 1;
			anchored[v] = 1;
			s.extra_anchors++;
		}
	}
	s.num_anchors = static_cast<int>(std::count(anchored.begin(), anchored.end(), 1));
	return anchored;
}

/** Spanning forest rooted at the anchors, as (edge index, traversed from→to) in breadth-first order:
 * edges between consecutive ids first (the odometry chain), then the others, each in file order. */
std::vector<std::pair<int, bool>> odometry_tree_order(const GraphIndex& gi, const std::vector<char>& anchored)
{
	const int n = static_cast<int>(gi.ids.size());
	const int m = static_cast<int>(gi.edges.size());
	std::vector<int> order(m);
	std::iota(order.begin(), order.end(), 0);
	const auto sequential = [&](int k) { return std::abs(gi.ids[gi.edges[k].first] - gi.ids[gi.edges[k].second]) == 1; };
	std::stable_partition(order.begin(), order.end(), sequential);
	UnionFind uf(n + 1);  // n: a virtual root joining all anchors
	for (int v = 0; v < n; v++)
		if (anchored[v]) uf.unite(v, n);
	std::vector<std::vector<int>> tree(n);
	for (int k : order)
		if (uf.unite(gi.edges[k].first, gi.edges[k].second))
		{
			tree[gi.edges[k].first].push_back(k);
			tree[gi.edges[k].second].push_back(k);
		}
	for (auto& t : tree) std::sort(t.begin(), t.end());
	std::vector<char> reached(anchored.begin(), anchored.end());
	std::vector<int> queue;
	for (int v = 0; v < n; v++)
		if (anchored[v]) queue.push_back(v);
	std::vector<std::pair<int, bool>> out;
	for (size_t h = 0; h < queue.size(); h++)
		for (int k : tree[queue[h]])
		{
			const auto [a, b] = gi.edges[k];
			const int other = a == queue[h] ? b : a;
			if (reached[other]) continue;
			reached[other] = 1;
			out.emplace_back(k, other == b);
			queue.push_back(other);
		}
	return out;
}

/** Linear least-squares edge e = Ja·x_a + Jb·x_b − y (K right-hand sides), weighted by Ω. */
template <int D, int K>
struct LinearEdge
{
	int a = 0, b = 0;
	Eigen::Matrix<double, D, D> Ja, Jb, Omega;
	Eigen::Matrix<double, D, K> y;
};

/** The edge Ja·x_a + x_b − y between the vertices `ends` (Jb = I for every edge of the
 * initialisation). The blocks are Eigen expressions, assigned as they come. */
template <int D, int K, typename JaExpr, typename OmegaExpr, typename YExpr>
LinearEdge<D, K> linear_edge(const std::pair<int, int>& ends, const JaExpr& Ja, const OmegaExpr& Omega, const YExpr& y)
{
	LinearEdge<D, K> e;
	e.a = ends.first, e.b = ends.second;
	e.Ja = Ja;
	e.Jb.setIdentity();
	e.Omega = Omega;
	e.y = y;
	return e;
}

/** The normal equations H·x = g of Σ ‖e‖²_Ω over the free (non-anchored) vertices: H's upper blocks in
 * the order of `pattern.upper_blocks` (the diagonal and every edge between two free vertices, sorted,
 * without repeats), g per free vertex, the anchored x moved to the right-hand side. */
template <int D, int K>
struct AnchoredNormalEquations
{
	using Block = Eigen::Matrix<double, D, D, Eigen::RowMajor>;
	std::vector<int> free_index;  ///< per vertex: its index among the free ones, −1 if anchored
	int m = 0;					  ///< free vertices
	BlockPattern pattern;
	std::vector<Block> H;
	std::vector<Eigen::Matrix<double, D, K>> g;

	AnchoredNormalEquations(const std::vector<char>& anchored, const std::vector<LinearEdge<D, K>>& edges)
		: free_index(anchored.size(), -1)
	{
		for (size_t v = 0; v < anchored.size(); v++)
			if (!anchored[v]) free_index[v] = m++;
		pattern.block_sizes.assign(m, D);
		for (int i = 0; i < m; i++) pattern.upper_blocks.emplace_back(i, i);
		for (const auto& e : edges)
		{
			const int i = free_index[e.a], j = free_index[e.b];
			if (i >= 0 && j >= 0 && i != j) pattern.upper_blocks.emplace_back(std::min(i, j), std::max(i, j));
		}
		std::sort(pattern.upper_blocks.begin(), pattern.upper_blocks.end());
		pattern.upper_blocks.erase(std::unique(pattern.upper_blocks.begin(), pattern.upper_blocks.end()),
								   pattern.upper_blocks.end());
	}

	/** H's block (i, j), i ≤ j, of the pattern. */
	Block& block(int i, int j)
	{
		const auto& u = pattern.upper_blocks;
		return H[std::lower_bound(u.begin(), u.end(), std::make_pair(i, j)) - u.begin()];
	}

	/** Sums every edge's terms, given the anchored vertices' x. */
	void accumulate(const std::vector<LinearEdge<D, K>>& edges, const std::vector<Eigen::Matrix<double, D, K>>& X)
	{
		H.assign(pattern.upper_blocks.size(), Block::Zero());
		g.assign(m, Eigen::Matrix<double, D, K>::Zero());
		for (const auto& e : edges)
		{
			const int i = free_index[e.a], j = free_index[e.b];
			Eigen::Matrix<double, D, K> y = e.y;
			if (i < 0) y -= e.Ja * X[e.a];
			if (j < 0) y -= e.Jb * X[e.b];
			const Eigen::Matrix<double, D, D> OJa = e.Omega * e.Ja, OJb = e.Omega * e.Jb;
			if (i >= 0)
			{
				block(i, i) += e.Ja.transpose() * OJa;
				g[i] += OJa.transpose() * y;
			}
			if (j >= 0)
			{
				block(j, j) += e.Jb.transpose() * OJb;
				g[j] += OJb.transpose() * y;
			}
			if (i >= 0 && j >= 0)
			{
				if (i < j) block(i, j) += e.Ja.transpose() * OJb;
				else if (j < i) block(j, i) += e.Jb.transpose() * OJa;
				else block(i, i) += e.Ja.transpose() * OJb + e.Jb.transpose() * OJa;
			}
		}
	}
};

/** Minimises Σ ‖e‖²_Ω over the non-anchored x (anchored x are inputs): one sparse Cholesky
 * factorisation of the block normal equations, K back-substitutions. `chol` is created on first use
 * and reused by later calls with the same anchors and edge pairs (same pattern: one symbolic analysis). */
template <int D, int K>
void solve_anchored(const std::vector<char>& anchored, const std::vector<LinearEdge<D, K>>& edges,
					std::vector<Eigen::Matrix<double, D, K>>& X, std::unique_ptr<BlockCholesky>& chol,
					const char* what)
{
	AnchoredNormalEquations<D, K> ne(anchored, edges);
	if (ne.m == 0) return;
	ne.accumulate(edges, X);
	std::vector<const double*> blocks(ne.H.size());
	for (size_t k = 0; k < ne.H.size(); k++) blocks[k] = ne.H[k].data();
	if (!chol) chol = BlockCholesky::sparse(ne.pattern);
	if (!chol->factorize(blocks))
		throw std::runtime_error(std::string(what) + ": the normal equations are not positive definite");
	Eigen::VectorXd rhs(ne.m * D);
	for (int k = 0; k < K; k++)
	{
		for (int i = 0; i < ne.m; i++) rhs.template segment<D>(i * D) = ne.g[i].col(k);
		chol->solve(rhs.data());
		for (size_t v = 0; v < anchored.size(); v++)
			if (ne.free_index[v] >= 0) X[v].col(k) = rhs.template segment<D>(ne.free_index[v] * D);
	}
}

// ---------------------------------------------------------------- 3D
void odometry3(PoseGraph& g, const GraphIndex& gi, const std::vector<char>& anchored, bool rotations_too)
{
	for (const auto& [k, forward] : odometry_tree_order(gi, anchored))
	{
		const auto& e = g.edges3[k];
		auto& a = g.vertices3.at(e.from);
		auto& b = g.vertices3.at(e.to);
		if (forward)
		{
			if (rotations_too) b.q = (a.q * e.q).normalized();
			b.t = a.t + a.q * e.t;
		}
		else
		{
			if (rotations_too) a.q = (b.q * e.q.conjugate()).normalized();
			a.t = b.t - a.q * e.t;
		}
	}
}

/** Rotations: X_v = R_vᵀ (column k = row k of R_v); R_b = R_a·R_ab  ⇔  X_b = R_abᵀ·X_a. */
void chordal_rotations3(PoseGraph& g, const GraphIndex& gi, const std::vector<char>& anchored,
						std::unique_ptr<BlockCholesky>& chol)
{
	const int n = static_cast<int>(gi.ids.size());
	std::vector<Eigen::Matrix3d> X(n);
	for (int v = 0; v < n; v++) X[v] = g.vertices3.at(gi.ids[v]).q.toRotationMatrix().transpose();
	std::vector<LinearEdge<3, 3>> rot(g.edges3.size());
	for (size_t k = 0; k < g.edges3.size(); k++)
	{
		const auto& e = g.edges3[k];
		rot[k] = linear_edge<3, 3>(gi.edges[k], -e.q.toRotationMatrix().transpose(),
								   (e.information.bottomRightCorner<3, 3>().trace() / 3.0) * Eigen::Matrix3d::Identity(),
								   Eigen::Matrix3d::Zero());
	}
	solve_anchored<3, 3>(anchored, rot, X, chol, "chordal initialisation (rotations)");
	for (int v = 0; v < n; v++)
		if (!anchored[v]) g.vertices3.at(gi.ids[v]).q = Eigen::Quaterniond(project_to_so3(X[v].transpose())).normalized();
}

/** Positions given the rotations: the exact minimiser of ½ Σ [r_t; r_r]ᵀΛ[r_t; r_r] over t, i.e.
 * r_t + c with c = Λ_tt⁻¹Λ_tr·r_r, in the world frame: t_b − t_a − R_a(t_ab − c), Ω = R_a Λ_tt R_aᵀ. */
void chordal_positions3(PoseGraph& g, const GraphIndex& gi, const std::vector<char>& anchored,
						const PoseGraphInitOptions& o, std::unique_ptr<BlockCholesky>& chol)
{
	const int n = static_cast<int>(gi.ids.size());
	std::vector<Eigen::Vector3d> T(n);
	for (int v = 0; v < n; v++) T[v] = g.vertices3.at(gi.ids[v]).t;
	std::vector<LinearEdge<3, 1>> pos(g.edges3.size());
	for (size_t k = 0; k < g.edges3.size(); k++)
	{
		const auto& e = g.edges3[k];
		const auto& qa = g.vertices3.at(e.from).q;
		const auto& qb = g.vertices3.at(e.to).q;
		const Eigen::Matrix3d L_tt = e.information.topLeftCorner<3, 3>();
		const Eigen::Vector3d c = L_tt.ldlt().solve(e.information.topRightCorner<3, 3>() *
													detail::rotation_residual(e.q, qa, qb, o.rotation_error));
		const Eigen::Matrix3d Ra = qa.toRotationMatrix();
		pos[k] = linear_edge<3, 1>(gi.edges[k], -Eigen::Matrix3d::Identity(), Ra * L_tt * Ra.transpose(), Ra * (e.t - c));
	}
	solve_anchored<3, 1>(anchored, pos, T, chol, "chordal initialisation (positions)");
	for (int v = 0; v < n; v++) g.vertices3.at(gi.ids[v]).t = T[v];
}

// ---------------------------------------------------------------- 2D
void odometry2(PoseGraph& g, const GraphIndex& gi, const std::vector<char>& anchored, bool rotations_too)
{
	for (const auto& [k, forward] : odometry_tree_order(gi, anchored))
	{
		const auto& e = g.edges2[k];
		auto& a = g.vertices2.at(e.from);
		auto& b = g.vertices2.at(e.to);
		const Eigen::Vector2d p_ab(e.x, e.y);
		if (forward)
		{
			if (rotations_too) b.theta = wrap_to_pi(a.theta + e.theta);
			const Eigen::Vector2d p = Eigen::Vector2d(a.x, a.y) + rot2(a.theta) * p_ab;
			b.x = p.x(), b.y = p.y();
		}
		else
		{
			if (rotations_too) a.theta = wrap_to_pi(b.theta - e.theta);
			const Eigen::Vector2d p = Eigen::Vector2d(b.x, b.y) - rot2(a.theta) * p_ab;
			a.x = p.x(), a.y = p.y();
		}
	}
}

/** Rotations as unit complex numbers z = (cos θ, sin θ): z_b = R(θ_ab)·z_a. */
void chordal_rotations2(PoseGraph& g, const GraphIndex& gi, const std::vector<char>& anchored,
						std::unique_ptr<BlockCholesky>& chol)
{
	const int n = static_cast<int>(gi.ids.size());
	std::vector<Eigen::Vector2d> Z(n);
	for (int v = 0; v < n; v++)
	{
		const double th = g.vertices2.at(gi.ids[v]).theta;
		Z[v] = Eigen::Vector2d(std::cos(th), std::sin(th));
	}
	std::vector<LinearEdge<2, 1>> rot(g.edges2.size());
	for (size_t k = 0; k < g.edges2.size(); k++)
	{
		const auto& e = g.edges2[k];
		rot[k] = linear_edge<2, 1>(gi.edges[k], -rot2(e.theta), e.information(2, 2) * Eigen::Matrix2d::Identity(),
								   Eigen::Vector2d::Zero());
	}
	solve_anchored<2, 1>(anchored, rot, Z, chol, "chordal initialisation (rotations)");
	for (int v = 0; v < n; v++)
		if (!anchored[v]) g.vertices2.at(gi.ids[v]).theta = std::atan2(Z[v].y(), Z[v].x());
}

/** Positions given the headings, as chordal_positions3 in the plane. */
void chordal_positions2(PoseGraph& g, const GraphIndex& gi, const std::vector<char>& anchored,
						const PoseGraphInitOptions&, std::unique_ptr<BlockCholesky>& chol)
{
	const int n = static_cast<int>(gi.ids.size());
	std::vector<Eigen::Vector2d> P(n);
	for (int v = 0; v < n; v++) P[v] = Eigen::Vector2d(g.vertices2.at(gi.ids[v]).x, g.vertices2.at(gi.ids[v]).y);
	std::vector<LinearEdge<2, 1>> pos(g.edges2.size());
	for (size_t k = 0; k < g.edges2.size(); k++)
	{
		const auto& e = g.edges2[k];
		const auto& va = g.vertices2.at(e.from);
		const auto& vb = g.vertices2.at(e.to);
		const double r_theta = wrap_to_pi(vb.theta - va.theta - e.theta);
		const Eigen::Matrix2d L_pp = e.information.topLeftCorner<2, 2>();
		const Eigen::Vector2d c = L_pp.ldlt().solve(e.information.topRightCorner<2, 1>() * r_theta);
		const Eigen::Matrix2d Ra = rot2(va.theta);
		pos[k] = linear_edge<2, 1>(gi.edges[k], -Eigen::Matrix2d::Identity(), Ra * L_pp * Ra.transpose(),
								   Ra * (Eigen::Vector2d(e.x, e.y) - c));
	}
	solve_anchored<2, 1>(anchored, pos, P, chol, "chordal initialisation (positions)");
	for (int v = 0; v < n; v++)
	{
		auto& vx = g.vertices2.at(gi.ids[v]);
		vx.x = P[v].x(), vx.y = P[v].y();
	}
}

/** The chordal initialisation: rotations relaxed and projected, then positions given them (without
 * solve_positions: composed along the odometry tree). Both solves share one pattern, so `chol`'s
 * symbolic analysis is done once. */
void chordal(PoseGraph& g, const GraphIndex& gi, const std::vector<char>& anchored, const PoseGraphInitOptions& o)
{
	const bool planar = g.is_2d();
	std::unique_ptr<BlockCholesky> chol;
	(planar ? chordal_rotations2 : chordal_rotations3)(g, gi, anchored, chol);
	if (o.solve_positions) (planar ? chordal_positions2 : chordal_positions3)(g, gi, anchored, o, chol);
	else (planar ? odometry2 : odometry3)(g, gi, anchored, false);
}
}  // namespace

PoseGraphInit parse_pose_graph_init(const std::string& name) { return parse_enum<PoseGraphInit>(name, "initialisation"); }

std::string to_string(PoseGraphInit init) { return enum_name(init); }

std::string PoseGraphInitSummary::brief() const
{
	char buf[200];
	std::snprintf(buf, sizeof buf, "%s: %d component(s), %d anchor(s) (%d for components without a fixed vertex), %.3f s",
				  to_string(method).c_str(), num_components, num_anchors, extra_anchors, time_s);
	return buf;
}

PoseGraphInitSummary initialize_pose_graph(PoseGraph& g, const PoseGraphInitOptions& o)
{
	const auto t0 = SteadyClock::now();
	PoseGraphInitSummary s;
	s.method = o.method;
	if (g.num_vertices() == 0) return s;
	const GraphIndex gi = index_graph(g);
	const std::vector<char> anchored = choose_anchors(g, gi, s);
	if (o.method == PoseGraphInit::Odometry)
	{
		if (g.is_2d()) odometry2(g, gi, anchored, true);
		else odometry3(g, gi, anchored, true);
	}
	else if (o.method == PoseGraphInit::Chordal)
		chordal(g, gi, anchored, o);
	if (const std::string bad = g.first_non_finite_vertex(); !bad.empty())
		throw std::runtime_error(to_string(o.method) + " initialisation gave a non-finite value to " + bad +
								 ": the edge measurements or information matrices overflow its computation");
	s.time_s = seconds_since(t0);
	return s;
}
}  // namespace swba::problems

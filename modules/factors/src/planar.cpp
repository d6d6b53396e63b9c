#include <swba/factors/planar.h>

#include <swba/core/scratch.h>

#include <Eigen/Core>
#include <algorithm>
#include <stdexcept>
#include <string>

namespace swba
{
namespace
{
using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/** Throws unless `sel` is non-empty, strictly increasing and inside [0, n). */
void check_selection(const std::vector<int>& sel, int n, const std::string& what)
{
	if (sel.empty()) throw std::invalid_argument(what + ": empty selection");
	for (std::size_t i = 0; i < sel.size(); i++)
		if (sel[i] < 0 || sel[i] >= n || (i > 0 && sel[i] <= sel[i - 1]))
			throw std::invalid_argument(what + ": selection must be increasing indices in [0, " + std::to_string(n) +
										")");
}

std::vector<int> selected_dims(const Factor& inner, const std::vector<std::vector<int>>& coords)
{
	if (static_cast<int>(coords.size()) != inner.num_variables())
		throw std::invalid_argument("SubspaceFactor: one coordinate list per variable of the inner factor");
	std::vector<int> dims;
	for (int i = 0; i < inner.num_variables(); i++)
	{
		const int n = inner.tangent_dims()[i];
		if (!coords[i].empty()) check_selection(coords[i], n, "SubspaceFactor variable " + std::to_string(i));
		dims.push_back(coords[i].empty() ? n : static_cast<int>(coords[i].size()));
	}
	return dims;
}
}  // namespace

SubspaceManifold::SubspaceManifold(std::shared_ptr<const Manifold> base, std::vector<int> coordinates)
	: base_(std::move(base)), coords_(std::move(coordinates))
{
	if (!base_) throw std::invalid_argument("SubspaceManifold: no base manifold");
	check_selection(coords_, base_->tangent_size(), "SubspaceManifold");
}

void SubspaceManifold::plus(const double* x, const double* delta, double* x_plus) const
{
	const std::size_t n = static_cast<std::size_t>(base_->tangent_size());
	Scratch<double, 16> full(n);
	std::fill_n(full.data(), n, 0.0);
	for (std::size_t i = 0; i < coords_.size(); i++) full.data()[coords_[i]] = delta[i];
	base_->plus(x, full.data(), x_plus);
}

void SubspaceManifold::minus(const double* y, const double* x, double* delta) const
{
	Scratch<double, 16> full(static_cast<std::size_t>(base_->tangent_size()));
	base_->minus(y, x, full.data());
	for (std::size_t i = 0; i < coords_.size(); i++) delta[i] = full.data()[coords_[i]];
}

std::shared_ptr<const SubspaceManifold> planar_pose_manifold()
{
	static const auto m = std::make_shared<const SubspaceManifold>(SE3Manifold::instance(), planar_pose_coordinates());
	return m;
}

std::shared_ptr<const SubspaceManifold> planar_point_manifold()
{
	static const auto m = std::make_shared<const SubspaceManifold>(euclidean_manifold(3), std::vector<int>{0, 1});
	return m;
}

SubspaceFactor::SubspaceFactor(std::shared_ptr<const Factor> inner, std::vector<int> residual_rows,
							   std::vector<std::vector<int>> tangent_coordinates)
	: Factor(static_cast<int>(residual_rows.size()), selected_dims(*inner, tangent_coordinates)),
	  inner_(std::move(inner)),
	  rows_(std::move(residual_rows)),
	  coords_(std::move(tangent_coordinates))
{
	check_selection(rows_, inner_->residual_dim(), "SubspaceFactor residual rows");
}

bool SubspaceFactor::evaluate(const double* const* x, double* residual, double* const* jacobians) const
{
	// The inner factor's residual, then its full Jacobian blocks, in one scratch buffer.
	const int m = inner_->residual_dim(), n = num_variables();
	const auto& full_dims = inner_->tangent_dims();
	std::size_t size = static_cast<std::size_t>(m);
	for (int i = 0; jacobians && i < n; i++)
		if (jacobians[i]) size += static_cast<std::size_t>(m * full_dims[i]);
	Scratch<double, 128> buffer(size);
	Scratch<double*, 8> full(static_cast<std::size_t>(n));
	double* next = buffer.data() + m;
	for (int i = 0; i < n; i++)
	{
		full.data()[i] = jacobians && jacobians[i] ? next : nullptr;
		if (full.data()[i]) next += m * full_dims[i];
	}
	if (!inner_->evaluate(x, buffer.data(), jacobians ? full.data() : nullptr)) return false;
	const int rows = residual_dim();
	for (int k = 0; k < rows; k++) residual[k] = buffer.data()[rows_[k]];
	for (int i = 0; jacobians && i < n; i++)
	{
		if (!jacobians[i]) continue;
		const int cols = tangent_dims()[i];
		Eigen::Map<RowMajor> J(jacobians[i], rows, cols);
		const Eigen::Map<const RowMajor> F(full.data()[i], m, full_dims[i]);
		for (int k = 0; k < rows; k++)
			for (int c = 0; c < cols; c++) J(k, c) = F(rows_[k], coords_[i].empty() ? c : coords_[i][c]);
	}
	return true;
}
}  // namespace swba

#include <swba/factors/linear_prior.h>

#include <stdexcept>

namespace swba
{
std::vector<int> LinearPriorFactor::dims_of(const std::vector<std::shared_ptr<const Manifold>>& m)
{
	std::vector<int> d;
	for (const auto& x : m)
	{
		if (!x) throw std::invalid_argument("LinearPriorFactor: null manifold");
		d.push_back(x->tangent_size());
	}
	return d;
}

LinearPriorFactor::LinearPriorFactor(Eigen::MatrixXd J, Eigen::VectorXd e, std::vector<std::vector<double>> x_lin,
									 std::vector<std::shared_ptr<const Manifold>> manifolds)
	: Factor(static_cast<int>(std::max<Eigen::Index>(J.rows(), 1)), dims_of(manifolds)),
	  J_(std::move(J)),
	  e_(std::move(e)),
	  x_lin_(std::move(x_lin)),
	  manifolds_(std::move(manifolds))
{
	if (J_.rows() == 0) throw std::invalid_argument("LinearPriorFactor: zero-rank prior");
	if (e_.size() != J_.rows()) throw std::invalid_argument("LinearPriorFactor: e and J row counts differ");
	if (x_lin_.size() != manifolds_.size()) throw std::invalid_argument("LinearPriorFactor: one x_lin per variable");
	offsets_.push_back(0);
	for (size_t i = 0; i < manifolds_.size(); i++)
	{
		if (static_cast<int>(x_lin_[i].size()) != manifolds_[i]->ambient_size())
			throw std::invalid_argument("LinearPriorFactor: x_lin has the wrong ambient size");
		offsets_.push_back(offsets_.back() + manifolds_[i]->tangent_size());
	}
	if (offsets_.back() != J_.cols()) throw std::invalid_argument("LinearPriorFactor: J has the wrong column count");
}

bool LinearPriorFactor::evaluate(const double* const* x, double* residual, double* const* jacobians) const
{
	Eigen::VectorXd d(J_.cols());
	for (size_t i = 0; i < manifolds_.size(); i++)
		manifolds_[i]->minus(x[i], x_lin_[i].data(), d.data() + offsets_[i]);
	Eigen::Map<Eigen::VectorXd> r(residual, J_.rows());
	r = e_ + J_ * d;
	if (jacobians)
		for (size_t i = 0; i < manifolds_.size(); i++)
			if (jacobians[i])
			{
				const int n = manifolds_[i]->tangent_size();
				Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> Ji(
					jacobians[i], J_.rows(), n);
				Ji = J_.middleCols(offsets_[i], n);
			}
	return true;
}
}  // namespace swba

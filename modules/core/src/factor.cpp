#include <swba/core/factor.h>

#include <Eigen/Cholesky>
#include <stdexcept>
#include <string>

namespace swba
{
Factor::Factor(int residual_dim, std::vector<int> tangent_dims)
	: residual_dim_(residual_dim), tangent_dims_(std::move(tangent_dims))
{
	if (residual_dim <= 0) throw std::invalid_argument("Factor: residual dimension must be positive");
	for (int d : tangent_dims_)
		if (d <= 0) throw std::invalid_argument("Factor: tangent dimensions must be positive");
}

void Factor::set_information(const Eigen::MatrixXd& information)
{
	const int m = residual_dim_;
	if (information.rows() != m || information.cols() != m)
		throw std::invalid_argument("Factor: information matrix must be " + std::to_string(m) + "x" +
									std::to_string(m));
	if (!information.allFinite())
		throw std::invalid_argument("Factor: information matrix has non-finite entries");
	const double asym = (information - information.transpose()).cwiseAbs().maxCoeff();
	if (asym > 1e-9 * std::max(1.0, information.cwiseAbs().maxCoeff()))
		throw std::invalid_argument("Factor: information matrix is not symmetric");
	Eigen::LLT<Eigen::MatrixXd> llt(0.5 * (information + information.transpose()));
	if (llt.info() != Eigen::Success)
		throw std::invalid_argument("Factor: information matrix is not positive definite");
	sqrt_info_ = llt.matrixL().transpose();
}

void Factor::set_sqrt_information(const Eigen::MatrixXd& W)
{
	if (W.rows() != residual_dim_ || W.cols() != residual_dim_)
		throw std::invalid_argument("Factor: square-root information has the wrong size");
	sqrt_info_ = W;
}

void Factor::set_sigma(double sigma)
{
	if (!(sigma > 0)) throw std::invalid_argument("Factor: sigma must be > 0");
	sqrt_info_ = Eigen::MatrixXd::Identity(residual_dim_, residual_dim_) / sigma;
}

bool Factor::evaluate_whitened(const double* const* x, double* residual, double* const* jacobians) const
{
	if (!evaluate(x, residual, jacobians)) return false;
	if (sqrt_info_.size() == 0) return true;
	const int m = residual_dim_;
	Eigen::Map<Eigen::VectorXd> r(residual, m);
	r = sqrt_info_ * r;
	if (jacobians)
	{
		for (int i = 0; i < num_variables(); i++)
		{
			if (!jacobians[i]) continue;
			Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> J(
				jacobians[i], m, tangent_dims_[i]);
			J = (sqrt_info_ * J).eval();
		}
	}
	return true;
}
}  // namespace swba

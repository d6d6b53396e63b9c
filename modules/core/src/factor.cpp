#include <swba/core/factor.h>
#include <swba/core/scratch.h>

#include <Eigen/Cholesky>
#include <stdexcept>
#include <string>
#include <vector>

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
	const double* W = sqrt_info_.data();  // column-major m×m
	// y ← W y for a strided column y of length m, through a stack copy (no heap temporaries: this
	// runs per factor per evaluation). Sums are formed in column order k = 0..m−1.
	auto whiten = [&](double* y, int stride, double* tmp) {
		for (int k = 0; k < m; k++) tmp[k] = y[k * stride];
		for (int i = 0; i < m; i++)
		{
			double acc = W[i] * tmp[0];
			for (int k = 1; k < m; k++) acc += W[k * m + i] * tmp[k];
			y[i * stride] = acc;
		}
	};
	Scratch<double, 32> scratch(static_cast<std::size_t>(m));
	double* tmp = scratch.data();
	whiten(residual, 1, tmp);
	if (jacobians)
	{
		for (int i = 0; i < num_variables(); i++)
		{
			if (!jacobians[i]) continue;
			const int n = tangent_dims_[i];
			for (int c = 0; c < n; c++) whiten(jacobians[i] + c, n, tmp);  // row-major m×n: column c
		}
	}
	return true;
}
}  // namespace swba

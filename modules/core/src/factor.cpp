#include <swba/core/factor.h>
#include <swba/core/scratch.h>

#include <Eigen/Cholesky>
#include <algorithm>
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
	store_sqrt_information(llt.matrixL().transpose());
}

void Factor::set_sqrt_information(const Eigen::MatrixXd& W)
{
	if (W.rows() != residual_dim_ || W.cols() != residual_dim_)
		throw std::invalid_argument("Factor: square-root information has the wrong size");
	store_sqrt_information(W);
}

void Factor::set_sigma(double sigma)
{
	if (!(sigma > 0)) throw std::invalid_argument("Factor: sigma must be > 0");
	store_sqrt_information(Eigen::MatrixXd::Identity(residual_dim_, residual_dim_) / sigma);
}

void Factor::store_sqrt_information(Eigen::MatrixXd W)
{
	sqrt_info_ = std::move(W);
	const int m = residual_dim_;
	row_span_.assign(2 * static_cast<std::size_t>(m), 0);
	for (int i = 0; i < m; i++)
	{
		int first = m, last = -1;  // an all-zero row: first > last
		for (int k = 0; k < m; k++)
		{
			if (sqrt_info_(i, k) == 0.0) continue;
			first = std::min(first, k);
			last = k;
		}
		row_span_[2 * i] = first;
		row_span_[2 * i + 1] = last;
	}
}

bool Factor::evaluate_whitened(const double* const* x, double* residual, double* const* jacobians) const
{
	if (!evaluate(x, residual, jacobians)) return false;
	if (sqrt_info_.size() == 0) return true;
	const int m = residual_dim_;
	const double* W = sqrt_info_.data();  // column-major m×m
	const int* span = row_span_.data();
	// y ← W y for a strided column y of length m, through a stack copy (no heap temporaries: this
	// runs per factor per evaluation). Sums are formed in column order over each row's non-zero span;
	// the zeros outside it would add only ±0 (for finite y).
	auto whiten = [&](double* y, int stride, double* tmp) {
		for (int k = 0; k < m; k++) tmp[k] = y[k * stride];
		for (int i = 0; i < m; i++)
		{
			const int first = span[2 * i], last = span[2 * i + 1];
			double acc = 0.0;
			if (first <= last)
			{
				acc = W[first * m + i] * tmp[first];
				for (int k = first + 1; k <= last; k++) acc += W[k * m + i] * tmp[k];
			}
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

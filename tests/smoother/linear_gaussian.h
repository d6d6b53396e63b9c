// A linear-Gaussian factor over Euclidean variables for the smoother tests: r = A·[x_1; …; x_k] − z.
#pragma once

#include <swba/core/factor.h>

#include <Eigen/Core>
#include <memory>
#include <utility>
#include <vector>

namespace swba::test
{
class LinearFactor final : public Factor
{
   public:
	LinearFactor(Eigen::MatrixXd A, Eigen::VectorXd z, std::vector<int> dims)
		: Factor(static_cast<int>(A.rows()), dims), A_(std::move(A)), z_(std::move(z))
	{
	}
	bool evaluate(const double* const* x, double* r, double* const* jac) const override
	{
		Eigen::VectorXd xs(A_.cols());
		int off = 0;
		for (int i = 0; i < num_variables(); i++)
			for (int c = 0; c < tangent_dims()[i]; c++) xs[off++] = x[i][c];
		Eigen::Map<Eigen::VectorXd>(r, A_.rows()) = A_ * xs - z_;
		off = 0;
		for (int i = 0; i < num_variables(); i++)
		{
			if (jac && jac[i])
				Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
					jac[i], A_.rows(), tangent_dims()[i]) = A_.middleCols(off, tangent_dims()[i]);
			off += tangent_dims()[i];
		}
		return true;
	}

   private:
	Eigen::MatrixXd A_;
	Eigen::VectorXd z_;
};

/** The difference factor x_j − x_i = d between two 2-D variables (i, j), standard deviation sigma. */
inline std::shared_ptr<LinearFactor> difference2(const Eigen::Vector2d& d, double sigma)
{
	Eigen::MatrixXd A(2, 4);
	A << -1, 0, 1, 0, 0, -1, 0, 1;
	auto f = std::make_shared<LinearFactor>(A, d, std::vector<int>{2, 2});
	f->set_sigma(sigma);
	return f;
}
}  // namespace swba::test

// Nearest positive-definite matrix by eigenvalue clipping (swba/core/positive_definite.h).
#include <swba/core/positive_definite.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace swba
{
PositiveDefiniteRepair repair_positive_definite(const Eigen::MatrixXd& a, double relative_floor)
{
	if (a.rows() != a.cols()) throw std::invalid_argument("repair_positive_definite: the matrix is not square");
	if (!a.allFinite()) throw std::invalid_argument("repair_positive_definite: the matrix has non-finite entries");
	if (!(relative_floor > 0 && relative_floor <= 1))
		throw std::invalid_argument("repair_positive_definite: relative_floor must be in (0, 1]");

	PositiveDefiniteRepair out;
	// (a + aᵀ)/2 is bit-identical to a when a is symmetric: valid input comes back unchanged.
	out.matrix = 0.5 * (a + a.transpose());
	if (Eigen::LLT<Eigen::MatrixXd>(out.matrix).info() == Eigen::Success) return out;

	const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(out.matrix);
	if (eig.info() != Eigen::Success)
		throw std::domain_error("repair_positive_definite: the eigen-decomposition did not converge");
	Eigen::VectorXd lambda = eig.eigenvalues();  // ascending
	out.repaired = true;
	out.min_eigenvalue = lambda(0);
	out.max_eigenvalue = lambda(lambda.size() - 1);
	if (!(out.max_eigenvalue > 0))
	{
		char buf[160];
		std::snprintf(buf, sizeof buf, "no positive eigenvalue (largest %.6g): no positive-definite matrix to clip to",
					  out.max_eigenvalue);
		throw std::domain_error(buf);
	}
	const double floor = relative_floor * out.max_eigenvalue;
	for (Eigen::Index i = 0; i < lambda.size(); i++)
		if (lambda(i) < floor)
		{
			lambda(i) = floor;
			out.clipped++;
		}
	const Eigen::MatrixXd& v = eig.eigenvectors();
	const Eigen::MatrixXd rebuilt = v * lambda.asDiagonal() * v.transpose();
	out.matrix = 0.5 * (rebuilt + rebuilt.transpose());
	return out;
}

Eigen::MatrixXd nearest_positive_definite(const Eigen::MatrixXd& a, double relative_floor)
{
	return repair_positive_definite(a, relative_floor).matrix;
}
}  // namespace swba

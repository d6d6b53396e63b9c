/** \file factor.h
 * The factor interface: a residual r(x_1, …, x_k) over k variables with analytic Jacobians in the
 * variables' tangent spaces, whitened by a square-root information matrix (GTSAM's NoiseModelFactor
 * pattern). Cost of one factor: ½ ρ(‖W r‖²), W the square-root information, ρ an optional loss. */
#pragma once

#include <Eigen/Core>
#include <vector>

namespace swba
{
class Factor
{
   public:
	/** `tangent_dims[i]` is the tangent size of the i-th variable the factor connects. */
	Factor(int residual_dim, std::vector<int> tangent_dims);
	virtual ~Factor() = default;

	int residual_dim() const { return residual_dim_; }
	int num_variables() const { return static_cast<int>(tangent_dims_.size()); }
	const std::vector<int>& tangent_dims() const { return tangent_dims_; }

	/** Evaluates the unwhitened residual and, for each non-null `jacobians[i]`, the row-major
	 * residual_dim × tangent_dims[i] Jacobian ∂r(x_i ⊞ δ)/∂δ at δ = 0.
	 * `x[i]` points to the i-th variable's stored value.
	 * Returns false when the residual is undefined at x (e.g. a projection behind the camera);
	 * the solver then drops the factor for that evaluation and counts it. */
	virtual bool evaluate(const double* const* x, double* residual, double* const* jacobians) const = 0;

	/** True when the Jacobians evaluate() writes do not depend on x (a factor linear in its variables'
	 * tangent offsets, like the marginalisation prior). Without a loss, the solver then forms the
	 * factor's Jᵀ J blocks once per solve instead of at every linearisation. Default false. */
	virtual bool constant_jacobian() const { return false; }

	/** Sets the information matrix Λ (residual_dim², symmetric positive definite); W = Lᵀ with Λ = L·Lᵀ.
	 * Throws std::invalid_argument if Λ is not symmetric positive definite. */
	void set_information(const Eigen::MatrixXd& information);
	/** Sets W directly (any residual_dim × residual_dim matrix). */
	void set_sqrt_information(const Eigen::MatrixXd& sqrt_information);
	/** Isotropic noise: W = I/σ. */
	void set_sigma(double sigma);
	bool has_sqrt_information() const { return sqrt_info_.size() > 0; }
	const Eigen::MatrixXd& sqrt_information() const { return sqrt_info_; }

	/** evaluate() followed by whitening of the residual and the requested Jacobians. */
	bool evaluate_whitened(const double* const* x, double* residual, double* const* jacobians) const;

   private:
	void store_sqrt_information(Eigen::MatrixXd W);

	int residual_dim_;
	std::vector<int> tangent_dims_;
	Eigen::MatrixXd sqrt_info_;  // empty = identity
	/// Per row i of W, the first and the last column with a non-zero entry (2i, 2i + 1): whitening
	/// skips the zeros of a triangular or diagonal W, which are most of them.
	std::vector<int> row_span_;
};
}  // namespace swba

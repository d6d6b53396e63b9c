/** \file planar.h
 * The planar (2D) model on the SE(3) machinery: a variable restricted to some of its tangent
 * coordinates (SubspaceManifold), and a factor decorator that keeps some residual rows and the
 * Jacobian columns of those coordinates (SubspaceFactor).
 *
 * A planar robot pose is an SE(3) value (same storage, so every SE(3) factor evaluates on it) whose
 * updates are (ρx, ρy, ωz): T ⊞ δ = T · Exp(δx, δy, 0, 0, 0, δθ). SE(2) is a subgroup of SE(3), so a
 * pose that starts level at z = 0 stays so: z, roll and pitch are not estimated and carry no
 * information. A planar landmark is a point whose updates are (x, y): it stays at the height it was
 * initialised at (the sensor's). A 2D range-bearing reading then keeps rows (range, yaw) of the 3D
 * model, and 2D odometry rows (ρx, ρy, ωz) of the SE(3) between-factor; for planar arguments the
 * dropped rows are identically zero. */
#pragma once

#include <swba/core/factor.h>
#include <swba/core/manifold.h>

#include <memory>
#include <vector>

namespace swba
{
/** A manifold whose updates move only the tangent coordinates `coordinates` of its base:
 * x ⊞ δ = x ⊞_base E·δ, y ⊟ x = Eᵀ·(y ⊟_base x), with E the columns of I at those coordinates. */
class SubspaceManifold final : public Manifold
{
   public:
	/** Throws std::invalid_argument when `coordinates` is empty, not strictly increasing or out of
	 * the base's tangent range. */
	SubspaceManifold(std::shared_ptr<const Manifold> base, std::vector<int> coordinates);
	int ambient_size() const override { return base_->ambient_size(); }
	int tangent_size() const override { return static_cast<int>(coords_.size()); }
	void plus(const double* x, const double* delta, double* x_plus) const override;
	/** Exact when y ⊟_base x lies in the subspace (e.g. two level poses); otherwise its projection. */
	void minus(const double* y, const double* x, double* delta) const override;

	const std::shared_ptr<const Manifold>& base() const { return base_; }
	const std::vector<int>& coordinates() const { return coords_; }

   private:
	std::shared_ptr<const Manifold> base_;
	std::vector<int> coords_;
};

/** SE(3) storage, updates (ρx, ρy, ωz): the pose of a robot on the plane z = 0. Shared instance. */
std::shared_ptr<const SubspaceManifold> planar_pose_manifold();
/** R³ storage, updates (x, y): a point at a fixed height. Shared instance. */
std::shared_ptr<const SubspaceManifold> planar_point_manifold();

/** Rows (ρx, ρy, ωz) of an SE(3) tangent vector: the planar part. */
inline const std::vector<int>& planar_pose_coordinates()
{
	static const std::vector<int> c{0, 1, 5};
	return c;
}

/** The rows `residual_rows` of `inner`, on variables whose manifolds keep only the tangent
 * coordinates `tangent_coordinates[i]` of the ones `inner` expects (an empty list keeps them all):
 * r = S·r_inner, J_i = S·J_inner,i·E_i. The information is this factor's own (`inner`'s is not
 * used). */
class SubspaceFactor final : public Factor
{
   public:
	/** Throws std::invalid_argument when the selections do not fit `inner`. */
	SubspaceFactor(std::shared_ptr<const Factor> inner, std::vector<int> residual_rows,
				   std::vector<std::vector<int>> tangent_coordinates);
	bool evaluate(const double* const* x, double* residual, double* const* jacobians) const override;

   private:
	std::shared_ptr<const Factor> inner_;
	std::vector<int> rows_;
	std::vector<std::vector<int>> coords_;
};
}  // namespace swba

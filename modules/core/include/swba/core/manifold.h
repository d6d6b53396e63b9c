/** \file manifold.h
 * Manifolds of the variables: how an update in the tangent space is applied (⊞) and undone (⊟).
 * Values are stored as plain arrays of `ambient_size()` doubles; updates have `tangent_size()`. */
#pragma once

#include <swba/core/lie.h>

#include <mrpt/poses/CPose3D.h>

#include <Eigen/Core>
#include <memory>

namespace swba
{
/** A smooth manifold with a retraction x ⊞ δ and its local inverse y ⊟ x. */
class Manifold
{
   public:
	virtual ~Manifold() = default;
	/** Number of doubles a value is stored in. */
	virtual int ambient_size() const = 0;
	/** Dimension of the tangent space (size of an update δ). */
	virtual int tangent_size() const = 0;
	/** x_plus = x ⊞ δ. `x_plus` may alias `x`. */
	virtual void plus(const double* x, const double* delta, double* x_plus) const = 0;
	/** δ = y ⊟ x, so that x ⊞ δ = y (locally). */
	virtual void minus(const double* y, const double* x, double* delta) const = 0;
};

/** R^n with x ⊞ δ = x + δ. */
class EuclideanManifold final : public Manifold
{
   public:
	explicit EuclideanManifold(int n);
	int ambient_size() const override { return n_; }
	int tangent_size() const override { return n_; }
	void plus(const double* x, const double* delta, double* x_plus) const override;
	void minus(const double* y, const double* x, double* delta) const override;

   private:
	int n_;
};

/** SE(3) with MRPT's right perturbation: T ⊞ δ = T · PseudoExp(δ), δ = [ρ(3), ω(3)],
 * exactly as mrpt::poses::Lie::SE<3>: R ← R·Exp(ω), t ← t + R·ρ.
 * Storage: 12 doubles, the 3×4 matrix [R | t] in row-major order. */
class SE3Manifold final : public Manifold
{
   public:
	static constexpr int kAmbient = 12;
	static constexpr int kTangent = 6;
	int ambient_size() const override { return kAmbient; }
	int tangent_size() const override { return kTangent; }
	void plus(const double* x, const double* delta, double* x_plus) const override;
	void minus(const double* y, const double* x, double* delta) const override;

	/** Shared instance (the manifold is stateless). */
	static std::shared_ptr<const SE3Manifold> instance();

	static void from_pose(const mrpt::poses::CPose3D& pose, double* x);
	static mrpt::poses::CPose3D to_pose(const double* x);
	/** The pose of rotation R (body → world) and translation t. */
	static mrpt::poses::CPose3D to_pose(const Eigen::Matrix3d& R, const Eigen::Vector3d& t);
};

/** Shared Euclidean manifolds of small sizes (1..16), created on first use. */
std::shared_ptr<const EuclideanManifold> euclidean_manifold(int n);

/** Row-major views of an SE(3) value's rotation and translation. */
using SE3Storage = Eigen::Matrix<double, 3, 4, Eigen::RowMajor>;
inline Eigen::Map<const SE3Storage> se3_view(const double* x) { return Eigen::Map<const SE3Storage>(x); }
inline Eigen::Map<SE3Storage> se3_view(double* x) { return Eigen::Map<SE3Storage>(x); }
}  // namespace swba

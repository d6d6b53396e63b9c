/** \file bal.h
 * "Bundle Adjustment in the Large" (BAL, Agarwal et al. 2010) problems: reader and writer of the
 * text format, conversion to a swba::Problem with SnavelyReprojectionFactor, PLY output, and the
 * `swba bal` application (read → solve → write).
 *
 * Format (whitespace separated):
 *   num_cameras num_points num_observations
 *   camera point x y                 (num_observations lines, one observation per line)
 *   9 numbers per camera             (ω Rodrigues(3), t(3), f, k1, k2; any line layout)
 *   3 numbers per point              (any line layout)
 * Observations are in pixels relative to the image centre; the Snavely model is described in
 * swba/factors/snavely_reprojection.h. */
#pragma once

#include <swba/core/loss.h>
#include <swba/nonlinear/problem.h>
#include <swba/nonlinear/solver.h>

#include <Eigen/Core>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace swba::io
{
struct BalObservation
{
	int camera = 0;
	int point = 0;
	double x = 0, y = 0;
};

/** A BAL problem in memory: parameters stored exactly as in the file. */
struct BalProblem
{
	static constexpr int kCameraParams = 9;
	static constexpr int kPointParams = 3;

	int num_cameras = 0;
	int num_points = 0;
	std::vector<BalObservation> observations;
	std::vector<double> cameras;  ///< kCameraParams per camera
	std::vector<double> points;   ///< kPointParams per point

	double* camera(int i) { return cameras.data() + kCameraParams * static_cast<size_t>(i); }
	const double* camera(int i) const { return cameras.data() + kCameraParams * static_cast<size_t>(i); }
	double* point(int j) { return points.data() + kPointParams * static_cast<size_t>(j); }
	const double* point(int j) const { return points.data() + kPointParams * static_cast<size_t>(j); }
};

/** Malformed BAL input: what() is "<source>:<line>: <reason>"; line() is 1-based. */
class BalParseError : public std::runtime_error
{
   public:
	BalParseError(const std::string& source, int line, const std::string& reason);
	int line() const { return line_; }

   private:
	int line_;
};

/** True when this build reads bzip2-compressed files (libbz2 linked into swba::io). */
bool bal_bzip2_supported();

/** Reads a BAL file; bzip2-compressed content ("BZh" magic) is decompressed when
 * bal_bzip2_supported(). Throws std::runtime_error if the file cannot be read and BalParseError
 * (with the line) on a truncated file, a header/count mismatch, an out-of-range camera or point
 * index, a non-numeric or non-finite number. Points behind their cameras are accepted. */
BalProblem read_bal(const std::string& path);

/** Parses BAL text; `source` names it in error messages. */
BalProblem parse_bal(const std::string& text, const std::string& source = "<bal>");

/** Writes `problem` in the BAL format (numbers with 17 significant digits, so that reading the file
 * back gives the same doubles). Throws std::runtime_error if the file cannot be written. */
void write_bal(const std::string& path, const BalProblem& problem);

/** Number of observations whose point lies behind its camera (P.z ≥ 0 in the camera frame; the
 * Snavely cameras look along −z). */
int count_observations_behind_camera(const BalProblem& problem);

/** Camera centres −R(ω)ᵀt, in camera order. */
std::vector<Eigen::Vector3d> bal_camera_centres(const BalProblem& problem);

/** PLY with the camera centres (green) followed by the points (white). */
void write_bal_ply(const std::string& path, const BalProblem& problem);

/** The variables created for a BAL problem in a swba::Problem. */
struct BalVariables
{
	std::vector<VariableId> cameras;  ///< Euclidean(9), Group::Kept
	std::vector<VariableId> points;   ///< Euclidean(3), Group::Eliminable
	int num_unobserved_cameras = 0;   ///< set constant (they have no factor)
	int num_unobserved_points = 0;    ///< set constant (they have no factor)
};

/** Adds one variable per camera and point and one SnavelyReprojectionFactor per observation (with
 * `loss`, null = plain least squares). Cameras/points without observations are set constant. */
BalVariables add_bal_to_problem(const BalProblem& bal, Problem& problem,
								std::shared_ptr<const LossFunction> loss = nullptr);

/** Copies the variables' current values back into `bal`. */
void copy_values_to_bal(const Problem& problem, const BalVariables& vars, BalProblem& bal);

/** Options of the `swba bal` application. */
struct BalAppOptions
{
	std::string problem_path;        ///< BAL file (required)
	std::string ply_initial;         ///< PLY of the initial values (empty: not written)
	std::string ply_final;           ///< PLY of the solution (empty: not written)
	std::string write_problem;       ///< BAL file of the solution (empty: not written)
	std::string loss = "none";       ///< none | huber | cauchy
	double loss_scale = 1.0;         ///< loss scale a, in pixels. Default 1.
	SolverOptions solver;            ///< the LM options (progress_to_stdout is honoured)
};

struct BalAppResult
{
	int num_behind_camera = 0;       ///< initial observations with the point behind the camera
	Summary summary;
};

/** Reads, solves (printing the per-iteration table if options.solver.progress_to_stdout, then the
 * full report) and writes the requested outputs. Report lines go to `out`. */
BalAppResult run_bal_app(const BalAppOptions& options, std::ostream& out);
}  // namespace swba::io

// NEES from covariance files (see nees.h).
#include <swba/core/chi2.h>
#include <swba/core/file.h>
#include <swba/eval/nees.h>

#include "data_lines.h"

#include <mrpt/poses/Lie/SO.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <istream>
#include <map>
#include <ostream>
#include <sstream>
#include <stdexcept>

namespace swba::eval
{
namespace
{
constexpr std::size_t kColumns = 1 + 6 + 21;

/** The 28 numbers of a row; throws naming the column. */
std::vector<double> parse_numbers(const std::string& line, const std::string& source, std::size_t line_no)
{
	std::istringstream in(line);
	std::vector<double> v;
	std::string token;
	while (in >> token)
	{
		char* end = nullptr;
		const double x = std::strtod(token.c_str(), &end);
		if (end != token.c_str() + token.size())
			throw TrajectoryFileError(source, line_no, "column " + std::to_string(v.size() + 1) + ": '" + token +
														   "' is not a number");
		if (!std::isfinite(x))
			throw TrajectoryFileError(source, line_no, "column " + std::to_string(v.size() + 1) + " is not finite");
		v.push_back(x);
	}
	if (v.size() != kColumns)
		throw TrajectoryFileError(source, line_no,
								  std::to_string(v.size()) + " numbers, expected 28 (stamp, 6 position covariance "
															 "entries xx xy xz yy yz zz, 21 pose covariance entries)");
	return v;
}

/** Fills the symmetric n×n `m` from its upper triangle, row by row, starting at v[first]. */
template <class Matrix>
void fill_upper(Matrix& m, const std::vector<double>& v, std::size_t first)
{
	const int n = static_cast<int>(m.rows());
	std::size_t k = first;
	for (int i = 0; i < n; i++)
		for (int j = i; j < n; j++) m(i, j) = m(j, i) = v[k++];
}

template <class Matrix>
void write_upper(std::ostream& out, const Matrix& m)
{
	char buf[40];
	for (int i = 0; i < m.rows(); i++)
		for (int j = i; j < m.cols(); j++)
		{
			std::snprintf(buf, sizeof(buf), " %.17g", m(i, j));
			out << buf;
		}
}

Eigen::Vector3d translation(const mrpt::poses::CPose3D& p) { return Eigen::Vector3d(p.x(), p.y(), p.z()); }
}  // namespace

std::vector<CovarianceRow> read_covariance_file(std::istream& in, const std::string& source)
{
	std::vector<CovarianceRow> rows;
	detail::for_each_data_line(in, source, '#', [&](const std::string& line, std::size_t line_no) {
		const auto v = parse_numbers(line, source, line_no);
		CovarianceRow r;
		r.stamp = v[0];
		if (!rows.empty() && r.stamp < rows.back().stamp)
			throw TrajectoryFileError(source, line_no, "stamp decreases");
		fill_upper(r.position, v, 1);
		fill_upper(r.pose, v, 7);
		for (int i = 0; i < 3; i++)
			if (r.position(i, i) < 0) throw TrajectoryFileError(source, line_no, "negative position variance");
		for (int i = 0; i < 6; i++)
			if (r.pose(i, i) < 0) throw TrajectoryFileError(source, line_no, "negative pose variance");
		rows.push_back(r);
	});
	return rows;
}

std::vector<CovarianceRow> read_covariance_file(const std::string& path)
{
	std::ifstream f;
	try
	{
		f = open_input_file(path, std::ios::in, "covariance file");
	}
	catch (const std::exception& e)
	{
		throw TrajectoryFileError(path, 0, e.what());
	}
	return read_covariance_file(f, path);
}

void write_covariance_file(std::ostream& out, const std::vector<CovarianceRow>& rows)
{
	char buf[40];
	for (const auto& r : rows)
	{
		std::snprintf(buf, sizeof(buf), "%.17g", r.stamp);
		out << buf;
		write_upper(out, r.position);
		write_upper(out, r.pose);
		out << "\n";
	}
}

NeesValue nees(const Eigen::VectorXd& e, const Eigen::MatrixXd& P)
{
	const Eigen::Index n = e.size();
	if (P.rows() != n || P.cols() != n) throw std::invalid_argument("error and covariance differ in size");
	std::vector<Eigen::Index> used;
	for (Eigen::Index i = 0; i < n; i++)
	{
		if (P(i, i) != 0)
		{
			used.push_back(i);
			continue;
		}
		if (!P.row(i).isZero(0) || !P.col(i).isZero(0))
			throw std::invalid_argument("dof " + std::to_string(i) + " has zero variance but non-zero covariances");
	}
	if (used.empty()) throw std::invalid_argument("every dof has zero variance");
	const auto m = static_cast<Eigen::Index>(used.size());
	Eigen::MatrixXd Pu(m, m);
	Eigen::VectorXd eu(m);
	for (Eigen::Index i = 0; i < m; i++)
	{
		eu(i) = e(used[static_cast<std::size_t>(i)]);
		for (Eigen::Index j = 0; j < m; j++) Pu(i, j) = P(used[static_cast<std::size_t>(i)], used[static_cast<std::size_t>(j)]);
	}
	// LDLᵀ: exact on a diagonal covariance (eᵢ²/Pᵢᵢ), and its D says whether P is positive definite.
	const Eigen::LDLT<Eigen::MatrixXd> ldlt(Pu);
	if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().array() > 0).all())
		throw std::invalid_argument("covariance is not positive definite");
	return {eu.dot(ldlt.solve(eu)), static_cast<int>(m)};
}

NeesValue position_nees(const mrpt::poses::CPose3D& estimate, const mrpt::poses::CPose3D& truth,
						const Eigen::Matrix3d& covariance)
{
	const Eigen::VectorXd e = translation(truth) - translation(estimate);
	return nees(e, covariance);
}

Eigen::Matrix<double, 6, 1> pose_error_tangent(const mrpt::poses::CPose3D& estimate, const mrpt::poses::CPose3D& truth)
{
	const Eigen::Matrix3d Re = estimate.getRotationMatrix().asEigen();
	const Eigen::Matrix3d Rt = truth.getRotationMatrix().asEigen();
	Eigen::Matrix<double, 6, 1> d;
	d.head<3>() = Re.transpose() * (translation(truth) - translation(estimate));
	const mrpt::math::CMatrixDouble33 dR(Eigen::Matrix3d(Re.transpose() * Rt));
	const auto w = mrpt::poses::Lie::SO<3>::log(dR);
	d.tail<3>() = Eigen::Vector3d(w[0], w[1], w[2]);
	return d;
}

NeesValue pose_nees(const mrpt::poses::CPose3D& estimate, const mrpt::poses::CPose3D& truth,
					const Eigen::Matrix<double, 6, 6>& covariance)
{
	const Eigen::VectorXd d = pose_error_tangent(estimate, truth);
	return nees(d, covariance);
}

RunNees run_nees(const Trajectory& estimate, const std::vector<CovarianceRow>& covariance,
				 const std::vector<mrpt::poses::CPose3D>& ground_truth, const std::string& source)
{
	if (covariance.size() != estimate.size())
		throw std::runtime_error(source + ": " + std::to_string(covariance.size()) + " rows, but the trajectory has " +
								 std::to_string(estimate.size()) + " poses (one row per pose expected)");
	if (ground_truth.empty()) throw std::runtime_error(source + ": no ground truth");
	const mrpt::poses::CPose3D origin = ground_truth.front();
	RunNees out;
	for (std::size_t i = 0; i < estimate.size(); i++)
	{
		const std::string where = source + ": row " + std::to_string(i + 1);
		const double t = estimate.stamps[i];
		if (covariance[i].stamp != t)
			throw std::runtime_error(where + ": stamp " + std::to_string(covariance[i].stamp) +
									 " differs from the trajectory's " + std::to_string(t));
		const double r = std::round(t);
		if (!(std::abs(t - r) < 1e-9) || r < 1 || r >= static_cast<double>(ground_truth.size()))
			throw std::runtime_error(where + ": stamp " + std::to_string(t) + " has no ground-truth row (" +
									 std::to_string(ground_truth.size()) + " rows)");
		const mrpt::poses::CPose3D truth = ground_truth[static_cast<std::size_t>(r)] - origin;
		const bool position_fixed = covariance[i].position.isZero(0), pose_fixed = covariance[i].pose.isZero(0);
		if (position_fixed && pose_fixed)
		{
			out.fixed_poses++;
			continue;
		}
		if (position_fixed != pose_fixed)
			throw std::runtime_error(where + ": the " + (position_fixed ? "position" : "pose") +
									 " covariance is zero but the " + (position_fixed ? "pose" : "position") + " one is not");
		try
		{
			out.position.push_back(position_nees(estimate.poses[i], truth, covariance[i].position));
			out.pose.push_back(pose_nees(estimate.poses[i], truth, covariance[i].pose));
		}
		catch (const std::invalid_argument& e)
		{
			throw std::runtime_error(where + ": " + e.what());
		}
		out.stamps.push_back(t);
	}
	return out;
}

NeesBand nees_band(std::size_t runs, int dof_sum, double probability)
{
	if (runs < 1 || dof_sum < 1) throw std::invalid_argument("nees_band: runs and dof must be >= 1");
	if (!(probability > 0 && probability < 1)) throw std::invalid_argument("nees_band: probability must be in (0, 1)");
	const double n = static_cast<double>(runs);
	return {chi2_quantile((1 - probability) / 2, dof_sum) / n, chi2_quantile((1 + probability) / 2, dof_sum) / n};
}

namespace
{
struct Accumulator
{
	std::size_t runs = 0;
	double position = 0, pose = 0;
	int position_dof = 0, pose_dof = 0;
};

void finish_series(AverageNeesSeries& s, const std::vector<std::size_t>& runs, double probability)
{
	std::size_t inside = 0;
	double sum = 0;
	std::map<std::pair<std::size_t, int>, NeesBand> bands;	// the quantile is costly: once per (n, dof)
	for (std::size_t k = 0; k < s.mean.size(); k++)
	{
		const auto key = std::make_pair(runs[k], s.dof_sum[k]);
		auto it = bands.find(key);
		if (it == bands.end()) it = bands.emplace(key, nees_band(runs[k], s.dof_sum[k], probability)).first;
		s.band.push_back(it->second);
		if (s.mean[k] >= it->second.low && s.mean[k] <= it->second.high) inside++;
		sum += s.mean[k];
	}
	if (!s.mean.empty())
	{
		s.share_in_band = static_cast<double>(inside) / static_cast<double>(s.mean.size());
		s.mean_over_steps = sum / static_cast<double>(s.mean.size());
	}
}
}  // namespace

AverageNees average_nees(const std::vector<RunNees>& runs, double probability)
{
	std::map<double, Accumulator> steps;
	for (const auto& run : runs)
		for (std::size_t i = 0; i < run.stamps.size(); i++)
		{
			Accumulator& a = steps[run.stamps[i]];
			a.runs++;
			a.position += run.position[i].value;
			a.pose += run.pose[i].value;
			a.position_dof += run.position[i].dof;
			a.pose_dof += run.pose[i].dof;
		}
	AverageNees out;
	for (const auto& [t, a] : steps)
	{
		const double n = static_cast<double>(a.runs);
		out.stamps.push_back(t);
		out.runs.push_back(a.runs);
		out.position.mean.push_back(a.position / n);
		out.position.dof_sum.push_back(a.position_dof);
		out.pose.mean.push_back(a.pose / n);
		out.pose.dof_sum.push_back(a.pose_dof);
	}
	finish_series(out.position, out.runs, probability);
	finish_series(out.pose, out.runs, probability);
	return out;
}
}  // namespace swba::eval

// swba simulate: simul-landmarks with a seed (see simulate.h).
#include <swba/apps/simulate.h>
#include <swba/core/file.h>

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CActionRobotMovement3D.h>
#include <mrpt/obs/CRawlog.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <spawn.h>
#include <sstream>
#include <stdexcept>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace swba::apps
{
namespace fs = std::filesystem;

void SimulateOptions::validate() const
{
	if (ini.empty()) throw std::invalid_argument("no simul-landmarks INI given");
	if (seed < 1) throw std::invalid_argument("--seed must be >= 1 (simul-landmarks draws a random seed for 0)");
	if (out_dir.empty()) throw std::invalid_argument("--out must not be empty");
	if (program.empty()) throw std::invalid_argument("no simul-landmarks program given");
	if (name.find('/') != std::string::npos) throw std::invalid_argument("--name must not contain '/'");
}

std::string SimulateOptions::output_name() const
{
	return name.empty() ? fs::path(ini).stem().string() + "_seed" + std::to_string(seed) : name;
}

std::string simulation_ini(const std::string& ini_text, const std::string& source, long seed, const std::string& name)
{
	mrpt::config::CConfigFileMemory cfg(ini_text);
	std::vector<std::string> keys;
	cfg.getAllKeys("Params", keys);
	if (std::find(keys.begin(), keys.end(), "random_seed") == keys.end())
		throw std::runtime_error("simul-landmarks INI '" + source +
								 "': no [Params] random_seed (is it a simul-landmarks INI?)");
	cfg.write("Params", "random_seed", std::to_string(seed));
	cfg.write("Params", "outFile", name + ".rawlog");
	cfg.write("Params", "outDir", ".");
	cfg.write("Params", "show_in_3d", "false");
	return cfg.getContent();
}

namespace
{
/** Runs `program ini` in `cwd` with stdout and stderr into `log_path`; returns the exit status. */
int run_in(const std::string& program, const std::string& ini, const std::string& cwd, const std::string& log_path)
{
	posix_spawn_file_actions_t actions;
	posix_spawn_file_actions_init(&actions);
	posix_spawn_file_actions_addchdir_np(&actions, cwd.c_str());
	posix_spawn_file_actions_addopen(&actions, 1, log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
	posix_spawn_file_actions_adddup2(&actions, 1, 2);
	std::vector<char*> argv = {const_cast<char*>(program.c_str()), const_cast<char*>(ini.c_str()), nullptr};
	pid_t pid = 0;
	const int rc = posix_spawnp(&pid, program.c_str(), &actions, nullptr, argv.data(), environ);
	posix_spawn_file_actions_destroy(&actions);
	if (rc != 0)
		throw std::runtime_error("cannot run '" + program + "': " + std::strerror(rc) +
								 (rc == ENOENT ? " (install the Debian package mrpt-apps)" : ""));
	int status = 0;
	while (waitpid(pid, &status, 0) < 0)
		if (errno != EINTR) throw std::runtime_error("waiting for '" + program + "': " + std::strerror(errno));
	return status;
}

/** Zero-covariance version of one movement whose increment is exactly zero; false for any other. */
bool declare_exact(mrpt::obs::CAction& action)
{
	if (auto* m3 = dynamic_cast<mrpt::obs::CActionRobotMovement3D*>(&action))
	{
		if (m3->poseChange.mean != mrpt::poses::CPose3D()) return false;
		m3->poseChange.cov.setZero();
		return true;
	}
	if (auto* m2 = dynamic_cast<mrpt::obs::CActionRobotMovement2D*>(&action))
	{
		// A 2D odometry movement is stored as its raw reading and motion model, and its Gaussian is
		// recomputed when read: a zero increment under the Gaussian model has covariance diag(minStdXY²,
		// minStdXY², minStdPHI²), so those become zero.
		if (m2->estimationMethod != mrpt::obs::CActionRobotMovement2D::emOdometry ||
			m2->rawOdometryIncrementReading != mrpt::poses::CPose2D())
			return false;
		mrpt::obs::CActionRobotMovement2D::TMotionModelOptions model = m2->motionModelConfiguration;
		model.modelSelection = mrpt::obs::CActionRobotMovement2D::mmGaussian;
		model.gaussianModel.minStdXY = 0;
		model.gaussianModel.minStdPHI = 0;
		m2->computeFromOdometry(m2->rawOdometryIncrementReading, model);
		return true;
	}
	return false;
}

bool non_empty_file(const fs::path& p)
{
	std::error_code ec;
	return fs::is_regular_file(p, ec) && fs::file_size(p, ec) > 0;
}
}  // namespace

std::size_t declare_unperturbed_odometry_exact(const std::string& rawlog)
{
	mrpt::obs::CRawlog log;
	if (!log.loadFromRawLogFile(rawlog)) throw std::runtime_error("cannot read rawlog '" + rawlog + "'");
	std::size_t count = 0;
	for (std::size_t i = 0; i < log.size(); i++)
	{
		if (log.getType(i) != mrpt::obs::CRawlog::etActionCollection) continue;
		for (auto& action : *log.getAsAction(i))
			if (action && declare_exact(*action)) count++;
	}
	if (count == 0) return 0;
	const std::string tmp = rawlog + ".exact";
	if (!log.saveToRawLogFile(tmp)) throw std::runtime_error("cannot write rawlog '" + tmp + "'");
	std::error_code ec;
	fs::rename(tmp, rawlog, ec);
	if (ec) throw std::runtime_error("cannot replace '" + rawlog + "': " + ec.message());
	return count;
}

SimulatedRawlog simulate_rawlog(const SimulateOptions& o, std::ostream& log)
{
	o.validate();
	const std::string name = o.output_name();
	const std::string ini_text = simulation_ini(read_text_file(o.ini, "simul-landmarks INI"), o.ini, o.seed, name);

	std::error_code ec;
	fs::create_directories(o.out_dir, ec);
	if (ec) throw std::runtime_error("cannot create output directory '" + o.out_dir + "': " + ec.message());
	const fs::path dir = fs::absolute(o.out_dir);
	SimulatedRawlog out;
	out.rawlog = (dir / (name + ".rawlog")).string();
	out.ground_truth = (dir / (name + "_ground_truth_robot_path.txt")).string();
	out.landmarks = (dir / (name + "_ground_truth.txt")).string();
	out.ini = (dir / (name + ".ini")).string();
	out.log = (dir / (name + ".simul-landmarks.log")).string();
	write_text_file_atomically(out.ini, ini_text);

	// A private working directory: simul-landmarks writes there, and two jobs never share one.
	const fs::path work = dir / (".simulate-" + name + "." + std::to_string(::getpid()));
	fs::remove_all(work, ec);
	fs::create_directories(work, ec);
	if (ec) throw std::runtime_error("cannot create '" + work.string() + "': " + ec.message());
	const fs::path log_file = work / "simul-landmarks.log";
	const int status = run_in(o.program, out.ini, work.string(), log_file.string());
	fs::rename(log_file, out.log, ec);
	const fs::path rawlog = work / (name + ".rawlog");
	const fs::path path = work / (name + ".rawlog_ground_truth_robot_path.txt");
	const fs::path landmarks = work / (name + ".rawlog_ground_truth.txt");
	if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || !non_empty_file(rawlog) || !non_empty_file(path))
	{
		fs::remove_all(work, ec);
		throw std::runtime_error(o.program + " failed on '" + o.ini + "' (seed " + std::to_string(o.seed) +
								 "): no rawlog written; see " + out.log);
	}
	if (!o.keep_declared_noise) out.exact_increments = declare_unperturbed_odometry_exact(rawlog.string());
	fs::rename(rawlog, out.rawlog);
	fs::rename(path, out.ground_truth);
	if (fs::exists(landmarks)) fs::rename(landmarks, out.landmarks);
	fs::remove_all(work, ec);
	log << "swba simulate: wrote " << out.rawlog << " (seed " << o.seed << ")\n";
	if (out.exact_increments > 0)
		log << "swba simulate: " << out.exact_increments
			<< " motionless odometry increments (written without noise by simul-landmarks) declared exact: zero "
			   "covariance instead of the moving steps' (--keep-declared-noise keeps them)\n";
	return out;
}
}  // namespace swba::apps

// swba jobs / merge / nees: seed lists, quoting, the job list and Slurm script, the manifest, and the
// NEES merge on a hand-made sweep (covariance files written here).
#include <gtest/gtest.h>
#include <swba/apps/nees.h>
#include <swba/apps/simulate.h>
#include <swba/apps/sweep.h>

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CActionRobotMovement3D.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/obs/CSensoryFrame.h>

#include <filesystem>
#include <fstream>
#include <sstream>

using namespace swba::apps;
namespace fs = std::filesystem;

namespace
{
fs::path fresh_dir(const std::string& name)
{
	const fs::path d = fs::temp_directory_path() / ("swba_test_sweep_" + name + "_" + std::to_string(::getpid()));
	fs::remove_all(d);
	fs::create_directories(d);
	return d;
}

void write(const fs::path& p, const std::string& text)
{
	fs::create_directories(p.parent_path());
	std::ofstream(p) << text;
}

std::string read(const fs::path& p)
{
	std::ifstream f(p);
	std::stringstream s;
	s << f.rdbuf();
	return s.str();
}

/** One "estimators" entry of a window row. */
std::string window_row(const std::string& label, const std::string& trajectory, const std::string& file)
{
	return R"({"name": "window", "label": ")" + label + R"(", "window": 5, "trajectory": ")" + trajectory +
		   R"(", "policy": "slam", "fej": true, "method": null, "file": ")" + file +
		   R"(", "poses": 2, "ape_trans": null, "ape_full": null, "seconds": 0.1, "ms_per_step": 1,
   "steps_processed": 2, "readings": null, "failed": false, "failed_step": null, "failure": null, "interrupted": false})";
}

/** A job's summary.json with the window's online and lagged rows (window_5.tum, window_5_lagged.tum);
 * `lagged` false: as a job killed before the end leaves it. */
std::string summary_json(const std::string& gt, bool lagged = true)
{
	return R"({"rawlog": "sim.rawlog", "ground_truth": ")" + gt + R"(", "steps": 2, "landmarks": 1, "estimators": [)" +
		   window_row("window W=5", "online", "window_5.tum") +
		   (lagged ? ", " + window_row("window W=5 lagged", "lagged", "window_5_lagged.tum") : "") + "]}";
}

/** Diagonal covariance row: position σ² (px, 1, 1), pose σ² (p0, 1, 1, 1, 1, 1). */
std::string cov_row(int t, double px, double p0)
{
	std::ostringstream s;
	s << t << " " << px << " 0 0 1 0 1";
	for (int i = 0; i < 6; i++)
		for (int j = i; j < 6; j++) s << " " << (i == j ? (i == 0 ? p0 : 1.0) : 0.0);
	return s.str() + "\n";
}
}  // namespace

TEST(SeedList, RangesAndLists)
{
	EXPECT_EQ(parse_seed_list("1-3,7"), (std::vector<long>{1, 2, 3, 7}));
	EXPECT_EQ(parse_seed_list("4"), (std::vector<long>{4}));
	EXPECT_THROW(parse_seed_list("0"), std::invalid_argument);
	EXPECT_THROW(parse_seed_list("3-1"), std::invalid_argument);
	EXPECT_THROW(parse_seed_list("1-3,2"), std::invalid_argument);
	EXPECT_THROW(parse_seed_list("1,,2"), std::invalid_argument);
	EXPECT_THROW(parse_seed_list("x"), std::invalid_argument);
}

TEST(ShellQuote, SafeWordsStayOthersAreSingleQuoted)
{
	EXPECT_EQ(shell_quote("/a/b-c_d.rawlog"), "/a/b-c_d.rawlog");
	EXPECT_EQ(shell_quote("a b"), "'a b'");
	EXPECT_EQ(shell_quote("it's"), "'it'\\''s'");
	EXPECT_EQ(shell_quote("$HOME;rm"), "'$HOME;rm'");
	EXPECT_EQ(shell_quote(""), "''");
}

TEST(PlanSweep, OneJobPerRawlogAndWindowTheWidestRunsEkfAndBatch)
{
	const fs::path d = fresh_dir("plan");
	SweepOptions o;
	o.rawlogs = {std::string(SWBA_MRPT_DATASETS) + "/kf-slam_6D_demo.rawlog"};
	o.run.windows = {3, 5};
	o.dir = (d / "s").string();
	o.swba = "/opt/swba";
	const SweepPlan plan = plan_sweep(o);
	ASSERT_EQ(plan.jobs.size(), 2u);
	const std::string s = (d / "s").string();
	EXPECT_EQ(plan.jobs[0].command, "/opt/swba run " + std::string(SWBA_MRPT_DATASETS) +
										"/kf-slam_6D_demo.rawlog --gt " + std::string(SWBA_MRPT_DATASETS) +
										"/kf-slam_6D_demo_ground_truth_robot_path.txt --config " + s +
										"/config_windows.ini --windows 3 --out " + s + "/jobs/kf-slam_6D_demo/w3");
	// The widest window's job runs the EKF, batch and causal rows (the batch starts from its lagged trajectory).
	EXPECT_NE(plan.jobs[1].command.find(" --config " + s + "/config.ini --windows 5 "), std::string::npos);
	const std::string sbatch = format_sbatch_script(plan);
	EXPECT_NE(sbatch.find("#SBATCH --array=1-2\n"), std::string::npos);
	EXPECT_NE(sbatch.find("sed -n \"${task}p\" \"$jobs\""), std::string::npos);

	std::ostringstream log;
	write_sweep(o, plan, log);
	EXPECT_EQ(read(d / "s" / "jobs.txt"), plan.jobs[0].command + "\n" + plan.jobs[1].command + "\n");
	const SweepPlan back = read_sweep_manifest(s);
	EXPECT_EQ(back.kind, SweepKind::Run);
	EXPECT_EQ(back.windows, (std::vector<int>{3, 5}));
	ASSERT_EQ(back.jobs.size(), 2u);
	EXPECT_EQ(back.jobs[1].command, plan.jobs[1].command);
	EXPECT_EQ(back.jobs[1].window, 5);
	EXPECT_EQ(back.groups[0].jobs, (std::vector<std::size_t>{1, 2}));
	// The other job's options: EKF, batch and causal off; both: no plots, no progress.
	RunOptions first, other;
	load_run_config(s + "/config.ini", first);
	load_run_config(s + "/config_windows.ini", other);
	EXPECT_TRUE(first.run_ekf);
	EXPECT_TRUE(first.run_batch);
	EXPECT_FALSE(other.run_ekf);
	EXPECT_FALSE(other.run_batch);
	EXPECT_FALSE(first.plots);
	fs::remove_all(d);
}

TEST(PlanSweep, NeesJobsSimulateTheirOwnRawlog)
{
	NeesOptions o;
	o.runs = 3;
	o.first_seed = 7;
	o.ini = std::string(SWBA_SHARE_DIR) + "/rawlogs/kf-slam_6D_noisy.ini";
	o.dir = "/tmp/nees_plan";
	o.swba = "swba";
	const SweepPlan plan = plan_sweep(o.sweep_options());
	ASSERT_EQ(plan.jobs.size(), 3u);
	EXPECT_EQ(plan.jobs[2].command,
			  "swba simulate " + o.ini + " --seed 9 --name kf-slam_6D_noisy_seed9 --out "
			  "/tmp/nees_plan/jobs/kf-slam_6D_noisy_seed9/rawlog && swba run "
			  "/tmp/nees_plan/jobs/kf-slam_6D_noisy_seed9/rawlog/kf-slam_6D_noisy_seed9.rawlog --config "
			  "/tmp/nees_plan/config.ini --out /tmp/nees_plan/jobs/kf-slam_6D_noisy_seed9/all");
}

TEST(MergeNees, HandMadeSweep)
{
	// Two runs of one estimator, 2 steps. Ground truth: the origin, then (1, 0, 0), (2, 0, 0).
	// Run 1 at t = 1 is 1 m short along x with σ²_x = 0.5 (position) and σ²_ρx = 0.5 (pose): NEES 2 and 2;
	// run 2 is exact: 0. Average at t = 1: 1 and 1. At t = 2 both exact: 0.
	const fs::path d = fresh_dir("nees");
	const fs::path gt = d / "gt.txt";
	write(gt, "% x y z yaw pitch roll\n0 0 0 0 0 0\n1 0 0 0 0 0\n2 0 0 0 0 0\n");
	SweepPlan plan;
	plan.kind = SweepKind::Nees;
	plan.dir = d.string();
	plan.simulate_ini = "/x/sim.ini";
	RunOptions config;  // what each job ran: W = 5, no EKF, no batch: 2 rows
	config.windows = {5};
	config.run_ekf = config.run_batch = false;
	write(d / "config.ini", format_run_config(config));
	for (int k = 0; k < 2; k++)
	{
		SweepGroup g;
		g.name = "seed" + std::to_string(k + 1);
		g.seed = k + 1;
		g.jobs = {static_cast<std::size_t>(k + 1)};
		plan.groups.push_back(g);
		SweepJob j;
		j.id = static_cast<std::size_t>(k + 1);
		j.group = static_cast<std::size_t>(k);
		j.dir = "jobs/" + g.name;
		plan.jobs.push_back(j);
		const fs::path jd = d / j.dir;
		write(jd / "summary.json", summary_json(gt.string()));
		write(jd / "window_5.tum", std::string(k == 0 ? "1 0 0 0 0 0 0 1\n" : "1 1 0 0 0 0 0 1\n") + "2 2 0 0 0 0 0 1\n");
		write(jd / "window_5.cov", cov_row(1, 0.5, 0.5) + cov_row(2, 1, 1));
		fs::copy_file(jd / "window_5.tum", jd / "window_5_lagged.tum");
		fs::copy_file(jd / "window_5.cov", jd / "window_5_lagged.cov");
	}
	MergeOptions mo;
	mo.dir = d.string();
	mo.plots = false;
	std::ostringstream out, log;
	const NeesReport r = merge_nees_sweep(plan, mo, out, log);
	ASSERT_EQ(r.estimators.size(), 2u);
	EXPECT_EQ(r.estimators[1].label, "window W=5 lagged");
	EXPECT_EQ(r.estimators[0].runs, 2u);
	EXPECT_EQ(r.estimators[0].average.position.mean, (std::vector<double>{1.0, 0.0}));
	EXPECT_EQ(r.estimators[0].average.pose.mean, (std::vector<double>{1.0, 0.0}));
	const std::string csv = read(d / "nees" / "nees.csv");
	EXPECT_NE(csv.find("\nwindow W=5,1,2,1,6,"), std::string::npos) << csv;  // 6 = N·d: 2 runs × 3 dof
	EXPECT_EQ(csv.rfind("label,stamp,runs,position_nees,position_dof_sum,", 0), 0u) << csv;
	EXPECT_NE(out.str().find("swba nees: 2 runs (seeds 1-2) of sim.ini, 2 steps"), std::string::npos) << out.str();
	// Mean 1 is inside the band of 2 runs × 3 dof, [χ²₆(0.025), χ²₆(0.975)] / 2 = [0.62, 7.22]; 0 is not: 50 %.
	EXPECT_NE(out.str().find("\nwindow W=5            2    3   [0.62, 7.22]   50.0 %    0.500"), std::string::npos)
		<< out.str();

	EXPECT_EQ(out.str().find("fixed dofs"), std::string::npos);

	// A planar estimator: z, roll and pitch fixed (zero rows and columns): 2 and 3 dof, and a note.
	for (const char* seed : {"seed1", "seed2"})
	{
		std::string planar;
		for (int t : {1, 2})
			planar += std::to_string(t) + " 1 0 0 1 0 0  1 0 0 0 0 0 1 0 0 0 0 0 0 0 0 0 0 0 0 0 1\n";
		write(d / "jobs" / seed / "window_5_lagged.cov", planar);
	}
	std::ostringstream planar_out;
	const NeesReport pr = merge_nees_sweep(plan, mo, planar_out, log);
	EXPECT_EQ(pr.estimators[1].average.position.dof_sum.front(), 4);
	EXPECT_EQ(pr.estimators[1].average.pose.dof_sum.front(), 6);
	EXPECT_NE(planar_out.str().find("note: window W=5 lagged: fixed dofs (zero rows and columns of its covariance, e.g. "
									"a planar model) left out: position NEES over 2 dof, pose NEES over 3 dof"),
			  std::string::npos)
		<< planar_out.str();

	// A job stopped before its end (its summary lacks the lagged row): named, not merged.
	write(d / "jobs" / "seed2" / "summary.json", summary_json(gt.string(), false));
	std::ostringstream log2;
	EXPECT_THROW(merge_nees_sweep(plan, mo, out, log2), std::runtime_error);
	EXPECT_NE(log2.str().find("job 2 (jobs/seed2): summary.json has 1 estimator rows, expected 2"), std::string::npos)
		<< log2.str();
	write(d / "jobs" / "seed2" / "summary.json", summary_json(gt.string()));

	// A missing covariance file: an error naming it.
	fs::remove(d / "jobs" / "seed2" / "window_5.cov");
	try
	{
		merge_nees_sweep(plan, mo, out, log);
		ADD_FAILURE() << "no error";
	}
	catch (const std::runtime_error& e)
	{
		EXPECT_NE(std::string(e.what()).find("no covariance file " + (d / "jobs" / "seed2" / "window_5.cov").string()),
				  std::string::npos)
			<< e.what();
	}
	fs::remove_all(d);
}

TEST(Simulate, IniGetsTheSeedAndOutputNames)
{
	const std::string ini = "# comment\n[Params]\nrandom_seed = 1   // >0: deterministic\nnSteps = 10\noutFile = x.rawlog\n"
							"outDir = /elsewhere\n[RANDOMSET_1]\nnLandmarks = 5\n";
	const std::string out = simulation_ini(ini, "t.ini", 42, "run_seed42");
	mrpt::config::CConfigFileMemory cfg(out);
	EXPECT_EQ(cfg.read_int("Params", "random_seed", 0), 42);
	EXPECT_EQ(cfg.read_string("Params", "outFile", ""), "run_seed42.rawlog");
	EXPECT_EQ(cfg.read_string("Params", "outDir", ""), ".");
	EXPECT_EQ(cfg.read_int("Params", "nSteps", 0), 10);
	EXPECT_EQ(cfg.read_int("RANDOMSET_1", "nLandmarks", 0), 5);
	EXPECT_THROW(simulation_ini("[Params]\nnSteps = 10\n", "t.ini", 1, "x"), std::runtime_error);
}

TEST(Simulate, ProgramThatWritesNothingIsAnErrorNamingItsLog)
{
	const fs::path d = fresh_dir("simulate");
	SimulateOptions o;
	o.ini = std::string(SWBA_SHARE_DIR) + "/rawlogs/kf-slam_6D_noisy.ini";
	o.seed = 3;
	o.out_dir = d.string();
	o.program = "true";  // exits 0 and writes nothing, as simul-landmarks does on a bad INI
	std::ostringstream log;
	try
	{
		simulate_rawlog(o, log);
		ADD_FAILURE() << "no error";
	}
	catch (const std::runtime_error& e)
	{
		EXPECT_NE(std::string(e.what()).find("true failed on '" + o.ini + "' (seed 3): no rawlog written; see " +
											 (d / "kf-slam_6D_noisy_seed3.simul-landmarks.log").string()),
				  std::string::npos)
			<< e.what();
	}
	o.program = "/nonexistent/simul-landmarks";
	EXPECT_THROW(simulate_rawlog(o, log), std::runtime_error);
	o.seed = 0;
	EXPECT_THROW(o.validate(), std::invalid_argument);
	fs::remove_all(d);
}

// simul-landmarks' motionless start: an exactly zero increment (3D mean, 2D raw reading) gets a zero
// covariance; a moving one keeps the declared covariance; observations are untouched.
TEST(Simulate, UnperturbedOdometryIsDeclaredExactAndNothingElseChanges)
{
	using namespace mrpt::obs;
	using mrpt::poses::CPose2D;
	using mrpt::poses::CPose3D;
	const fs::path d = fresh_dir("exact");
	const std::string path = (d / "sim.rawlog").string();
	CRawlog log;
	const auto movement3d = [](const CPose3D& mean) {
		CActionRobotMovement3D m;
		m.poseChange.mean = mean;
		m.poseChange.cov.setIdentity();
		m.poseChange.cov *= 0.0036;
		CActionCollection acts;
		acts.insert(m);
		return acts;
	};
	const auto movement2d = [](const CPose2D& reading) {
		CActionRobotMovement2D m;
		m.computeFromOdometry(reading, CActionRobotMovement2D::TMotionModelOptions());
		CActionCollection acts;
		acts.insert(m);
		return acts;
	};
	CSensoryFrame sf;
	auto obs = CObservationBearingRange::Create();
	obs->sensedData.resize(1);
	obs->sensedData[0].range = 2.5;
	sf.insert(obs);
	log.insert(sf);
	CActionCollection a0 = movement3d(CPose3D()), a1 = movement3d(CPose3D(0.2, 0, 0, 0.05, 0, 0));
	CActionCollection a2 = movement2d(CPose2D()), a3 = movement2d(CPose2D(0.2, 0, 0.1));
	for (auto* a : {&a0, &a1, &a2, &a3})
	{
		log.insert(*a);
		log.insert(sf);
	}
	ASSERT_TRUE(log.saveToRawLogFile(path));

	EXPECT_EQ(declare_unperturbed_odometry_exact(path), 2u);
	CRawlog back;
	ASSERT_TRUE(back.loadFromRawLogFile(path));
	ASSERT_EQ(back.size(), log.size());
	std::vector<mrpt::poses::CPose3DPDFGaussian> moves;
	for (std::size_t i = 0; i < back.size(); i++)
		if (back.getType(i) == CRawlog::etActionCollection)
		{
			mrpt::poses::CPose3DPDFGaussian g;
			ASSERT_TRUE(back.getAsAction(i)->getFirstMovementEstimation(g));
			moves.push_back(g);
		}
		else
		{
			const auto b = back.getAsObservations(i)->getObservationByClass<CObservationBearingRange>();
			ASSERT_TRUE(b);
			EXPECT_EQ(b->sensedData.at(0).range, 2.5f);
		}
	ASSERT_EQ(moves.size(), 4u);
	EXPECT_EQ(moves[0].cov.norm(), 0.0);  // motionless 3D
	EXPECT_DOUBLE_EQ(moves[1].cov(0, 0), 0.0036);  // moving 3D: as declared
	EXPECT_NEAR(moves[1].mean.x(), 0.2, 1e-12);
	EXPECT_EQ(moves[2].cov.norm(), 0.0);  // motionless 2D
	EXPECT_GT(moves[3].cov(0, 0), 0.0);   // moving 2D: the motion model's covariance
	EXPECT_EQ(declare_unperturbed_odometry_exact(path), 2u);  // idempotent: the same two, still zero
	fs::remove_all(d);
}

// swba run options: INI loading (strict keys, values, comments), list parsing, the default INI file.
#include <swba/apps/run_options.h>

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

namespace
{
using swba::estimators::LandmarkPolicy;
using swba::apps::load_run_config;
using swba::apps::load_run_config_text;
using swba::apps::RunOptions;

const std::string kDefaultIni = std::string(SWBA_SHARE_DIR) + "/config/swba_run.ini";

std::string load_error(const std::string& text)
{
	RunOptions o;
	try
	{
		load_run_config_text(text, "test.ini", o);
	}
	catch (const std::runtime_error& e)
	{
		return e.what();
	}
	ADD_FAILURE() << "no error for:\n" << text;
	return {};
}

/** An INI setting every key to a value different from its default. */
std::string non_default_ini()
{
	return "[run]\nrawlog = a.rawlog\nground_truth = a_gt.txt\nassociation_truth = a_ids.rawlog\nout_dir = elsewhere\nmax_steps = 7\n"
		   "batch = false\nbatch_max_iterations = 3\ncausal = true\nplots = false\nprogress = false\nverbose = true\n"
		   "[window]\nsizes = 3,4\npolicy = both\nfej = off\nlandmarks = xyz\nmodel = 2d\ngauge = prior\ngauge_prior_weight = 5\n"
		   "relinearized_poses = 4\nmarginalization_threshold = 0.5\ngate = true\ngate_probability = 0.5\nrobust_loss = huber\n"
		   "robust_probability = 0.75\ncovariances = false\n"
		   "association = nn\nreassociate = false\nassociation_pose_inflation = 4\nyoung_landmark_readings = 5\n"
		   "young_readings_test = false\n"
		   "[solver]\nmax_iterations = 4\nfunction_tolerance = 0.5\ngradient_tolerance = 0.25\n"
		   "parameter_tolerance = 0.125\nlinear_solver = dense-normal\ndense_max_dim = 9\nthreads = 2\n"
		   "[ekf]\nenabled = false\nmethods = kfIKFFull\nini_file = x.ini\n"
		   "[sensor]\nstd_range_m = 0.5\nstd_yaw_deg = 2\nstd_pitch_deg = 3\n"
		   "[odometry]\nmin_sigma_translation_m = 0.5\nmin_sigma_rotation_rad = 0.25\n"
		   "[sensors]\nimu = XSENS\npose_prior = MAP\nodometry = LIDAR\n"
		   "[inertial]\nkeyframes = poses\ngauge = fixed\nfirst_estimate_jacobians = false\nreintegrate_accel = 0.5\n"
		   "reintegrate_gyro = 0.25\n"
		   "[imu]\naccel_noise_density = 0.5\ngyro_noise_density = 0.25\naccel_random_walk = 0.125\n"
		   "gyro_random_walk = 0.0625\ngravity_z = -9.8\n";
}
}  // namespace

TEST(RunConfig, NonDefaultIniSetsEveryKey)
{
	RunOptions o;
	load_run_config_text(non_default_ini(), "nd.ini", o);
	const RunOptions d;
	// Every key's value differs from its default after loading: the table covers every key set above.
	for (const auto& k : swba::apps::run_config_key_table())
		EXPECT_NE(k.get(o), k.get(d)) << "[" << k.section << "] " << k.key << " not set by the INI";
	EXPECT_EQ(o.windows, (std::vector<int>{3, 4}));
	EXPECT_EQ(o.policies.size(), 2u);
	EXPECT_EQ(o.fej, std::vector<bool>{false});
	EXPECT_EQ(o.max_steps, 7u);
	EXPECT_FALSE(o.run_batch);
	EXPECT_TRUE(o.run_causal);
	EXPECT_EQ(o.ekf_methods, std::vector<std::string>{"kfIKFFull"});
	EXPECT_EQ(o.window.solver.max_iterations, 4);
	EXPECT_EQ(o.window.solver.num_threads, 2);
	EXPECT_NEAR(o.window.sensor.std_yaw, 2.0 * M_PI / 180.0, 1e-15);
	EXPECT_DOUBLE_EQ(o.window.sensor.std_range, 0.5);
	EXPECT_DOUBLE_EQ(o.window.odometry.min_sigma_rotation, 0.25);
	EXPECT_EQ(o.window.model, swba::estimators::PoseModel::Planar);
	EXPECT_TRUE(o.window.gate_readings);
	EXPECT_DOUBLE_EQ(o.window.gate_probability, 0.5);
	EXPECT_EQ(o.window.robust_loss, swba::RobustLoss::Huber);
	EXPECT_DOUBLE_EQ(o.window.robust_probability, 0.75);
	EXPECT_FALSE(o.window.covariances);
	EXPECT_EQ(o.window.association, swba::estimators::DataAssociation::NearestNeighbour);
	EXPECT_FALSE(o.window.reassociate);
	EXPECT_DOUBLE_EQ(o.window.association_pose_inflation, 4.0);
	EXPECT_EQ(o.inertial.measurements.keyframes, swba::estimators::KeyframeTimes::PoseReadings);
	EXPECT_EQ(o.inertial.gauge, swba::GaugeMode::Fixed);
	EXPECT_DOUBLE_EQ(o.inertial.measurements.noise.gyro_noise_density, 0.25);
}

TEST(RunConfig, DefaultIniHoldsTheBuiltInDefaults)
{
	// Start from options that differ everywhere, load the shipped INI: every key must come back to
	// its built-in default (so the file names every key, with the default value).
	RunOptions o;
	load_run_config_text(non_default_ini(), "nd.ini", o);
	load_run_config(kDefaultIni, o);
	EXPECT_EQ(swba::apps::format_run_config(o), swba::apps::format_run_config(RunOptions{}));
}

TEST(RunConfig, DefaultIniDocumentsEveryKeyWithItsDefault)
{
	std::ifstream f(kDefaultIni);
	ASSERT_TRUE(f) << kDefaultIni;
	std::stringstream ss;
	ss << f.rdbuf();
	const std::string text = ss.str();
	const RunOptions d;
	for (const auto& k : swba::apps::run_config_key_table())
	{
		const auto section = text.find("\n[" + k.section + "]\n");
		ASSERT_NE(section, std::string::npos) << k.section;
		const auto at = text.find("\n" + k.key + " =", section);  // the key of this section (names repeat)
		ASSERT_NE(at, std::string::npos) << k.key;
		ASSERT_LT(at, text.find("\n[", section + 1)) << "[" << k.section << "] " << k.key << " not in its section";
		// The comment just above the key states "(Default=<value>)".
		const auto comment_start = text.rfind("\n[", at) == std::string::npos ? 0 : text.rfind("\n[", at);
		const auto prev_key = text.rfind(" = ", at - 1);
		const auto from = std::max(comment_start, prev_key == std::string::npos ? 0 : prev_key);
		const std::string doc = text.substr(from, at - from);
		EXPECT_NE(doc.find("(Default=" + k.get(d) + ")"), std::string::npos)
			<< "[" << k.section << "] " << k.key << ": no '(Default=" << k.get(d) << ")' in its comment:\n"
			<< doc;
	}
	// The error-message key list states the same defaults.
	for (const auto& line : swba::apps::run_config_keys()) EXPECT_NE(line.find("(Default="), std::string::npos);
}

TEST(RunConfig, UnknownKeyIsAnErrorListingTheKnownKeys)
{
	const std::string msg = load_error("[window]\nsize = 5\n");
	EXPECT_NE(msg.find("test.ini"), std::string::npos) << msg;
	EXPECT_NE(msg.find("unknown key 'size' in section [window]"), std::string::npos) << msg;
	EXPECT_NE(msg.find("known keys: sizes, policy, fej, landmarks"), std::string::npos) << msg;
}

TEST(RunConfig, UnknownSectionIsAnError)
{
	const std::string msg = load_error("[windows]\nsizes = 5\n");
	EXPECT_NE(msg.find("unknown section [windows]"), std::string::npos) << msg;
	EXPECT_NE(msg.find("known sections: run, window, solver, ekf, sensor, odometry"), std::string::npos) << msg;
}

TEST(RunConfig, BadValuesNameTheKey)
{
	struct Case
	{
		std::string ini, expected;
	};
	for (const Case& c : std::vector<Case>{
			 {"[solver]\nmax_iterations = 10x\n", "[solver] max_iterations: '10x' is not an integer"},
			 {"[solver]\nmax_iterations = 0\n", "[solver] max_iterations: '0' must be an integer >= 1"},
			 {"[window]\nsizes = 1,5\n", "[window] sizes: window size must be in [2, 1000000], got 1"},
			 {"[window]\npolicy = fast\n", "[window] policy: unknown policy 'fast'"},
			 {"[window]\nfej = maybe\n", "[window] fej: unknown fej value 'maybe'"},
			 {"[window]\ngauge = loose\n", "[window] gauge: unknown gauge 'loose'"},
			 {"[run]\nbatch = perhaps\n", "[run] batch: 'perhaps' is not a boolean"},
			 {"[ekf]\nmethods = kfEKFNaive,kfFoo\n", "[ekf] methods: unknown EKF method 'kfFoo'"},
			 {"[ekf]\nmethods = kfIKF\n", "[ekf] methods: EKF method 'kfIKF' is not implemented by MRPT"},
			 {"[sensor]\nstd_range_m = -1\n", "[sensor] std_range_m: '-1' must be >= 0"},
			 {"[sensor]\nstd_yaw_deg = nan\n", "[sensor] std_yaw_deg: 'nan' is not finite"},
			 {"[solver]\nlinear_solver = magic\n", "[solver] linear_solver:"},
			 {"[window]\ngate_probability = 1\n", "[window] gate_probability: '1' must be in (0, 1)"},
			 {"[window]\nrobust_loss = tukey\n", "[window] robust_loss: unknown robust loss 'tukey'"},
			 {"[inertial]\nkeyframes = every\n", "[inertial] keyframes: unknown keyframe times 'every'"},
			 {"[inertial]\nreintegrate_gyro = 0\n", "[inertial] reintegrate_gyro: '0' must be > 0"},
			 {"# sizes\n[window]\nsizes 10\n", ":3: 'sizes 10' is neither a [section], a key = value line nor a comment"},
			 // MRPT would keep the last of the two (names compare case-insensitively, sections may repeat).
			 {"[window]\nsizes = 5\n[solver]\nthreads = 1\n[Window]\nSizes = 10\n",
			  ":6: [Window] Sizes is given twice (first on line 2)"},
		 })
	{
		const std::string msg = load_error(c.ini);
		EXPECT_NE(msg.find(c.expected), std::string::npos) << "INI:\n" << c.ini << "message: " << msg;
		EXPECT_EQ(msg.find('\n'), std::string::npos) << "one line: " << msg;
	}
}

TEST(RunConfig, CommentsAndLaterFilesWin)
{
	RunOptions o;
	load_run_config_text("# comment\n; other comment\n[window]\nsizes = 5, 10 // two windows\n", "a.ini", o);
	EXPECT_EQ(o.windows, (std::vector<int>{5, 10}));
	EXPECT_EQ(o.policies, std::vector<LandmarkPolicy>{LandmarkPolicy::Slam});  // untouched keys keep their value
	load_run_config_text("[window]\nsizes = 20\npolicy = constant-time\n", "b.ini", o);
	EXPECT_EQ(o.windows, (std::vector<int>{20}));
	EXPECT_EQ(o.policies, std::vector<LandmarkPolicy>{LandmarkPolicy::ConstantTime});
}

TEST(RunConfig, MissingFileIsAnError)
{
	RunOptions o;
	try
	{
		load_run_config("/nonexistent/run.ini", o);
		FAIL() << "no error";
	}
	catch (const std::runtime_error& e)
	{
		EXPECT_NE(std::string(e.what()).find("config '/nonexistent/run.ini': file does not exist"), std::string::npos)
			<< e.what();
	}
}

TEST(RunConfig, ListParsing)
{
	using namespace swba::estimators;
	using namespace swba::apps;
	EXPECT_EQ(parse_window_list("5,10,20,30"), (std::vector<int>{5, 10, 20, 30}));
	EXPECT_EQ(parse_window_list(" 7 , 7,3"), (std::vector<int>{7, 3}));  // duplicates dropped
	EXPECT_THROW(parse_window_list("5,,10"), std::invalid_argument);
	EXPECT_THROW(parse_window_list("5,"), std::invalid_argument);
	EXPECT_THROW(parse_window_list(""), std::invalid_argument);
	EXPECT_THROW(parse_window_list("5,x"), std::invalid_argument);
	EXPECT_THROW(parse_window_list("2.5"), std::invalid_argument);
	try
	{
		parse_window_list("1", "--windows");
		FAIL();
	}
	catch (const std::invalid_argument& e)
	{
		EXPECT_STREQ(e.what(), "--windows: window size must be in [2, 1000000], got 1");
	}
	// Too large: the message names the upper end, not the lower one.
	try
	{
		parse_window_list("10000000", "--windows");
		FAIL();
	}
	catch (const std::invalid_argument& e)
	{
		EXPECT_STREQ(e.what(), "--windows: window size must be in [2, 1000000], got 10000000");
	}
	EXPECT_EQ(parse_policy_list("both").size(), 2u);
	EXPECT_EQ(parse_policy_list("constant-time"), std::vector<LandmarkPolicy>{LandmarkPolicy::ConstantTime});
	EXPECT_EQ(parse_policy_list("map, slam,map"), (std::vector<LandmarkPolicy>{LandmarkPolicy::Map, LandmarkPolicy::Slam}));
	EXPECT_EQ(parse_policy_list("all").size(), 3u);
	EXPECT_THROW(parse_policy_list("slam,fast"), std::invalid_argument);
	EXPECT_THROW(parse_policy_list(","), std::invalid_argument);
	EXPECT_EQ(parse_fej_list("both"), (std::vector<bool>{true, false}));
	EXPECT_EQ(parse_fej_list("off"), std::vector<bool>{false});
	EXPECT_THROW(parse_fej_list("sometimes"), std::invalid_argument);
	EXPECT_EQ(parse_ekf_method_list("0,kfEKFAlaDavison,kfEKFNaive"),
			  (std::vector<std::string>{"kfEKFNaive", "kfEKFAlaDavison"}));
	EXPECT_THROW(parse_ekf_method_list("kfUKF"), std::invalid_argument);
}

TEST(RunConfig, ValidateRejectsBadCombinations)
{
	RunOptions o;
	EXPECT_NO_THROW(o.validate());
	o.windows = {1};
	EXPECT_THROW(o.validate(), std::invalid_argument);
	o = RunOptions{};
	o.windows.clear();
	o.run_ekf = false;
	o.run_batch = false;
	EXPECT_THROW(o.validate(), std::invalid_argument);
	o = RunOptions{};
	o.window.solver.num_threads = 0;
	EXPECT_THROW(o.validate(), std::invalid_argument);
}

TEST(RunConfig, WrittenConfigReadsBackToTheSameOptions)
{
	// DIR/config.ini of a run must reproduce the run's options with --config.
	RunOptions o;
	load_run_config_text(non_default_ini(), "nd.ini", o);
	o.ground_truth = "";  // an empty value written as "key = "
	const std::string text = swba::apps::format_run_config(o);
	RunOptions back;
	load_run_config_text(text, "written.ini", back);
	EXPECT_EQ(swba::apps::format_run_config(back), text);
	EXPECT_EQ(back.windows, o.windows);
	EXPECT_EQ(back.window.sensor.std_yaw, o.window.sensor.std_yaw);
}

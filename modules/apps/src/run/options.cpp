#include <swba/estimators/ekf_slam.h>
#include <swba/apps/run_options.h>

#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/system/filesystem.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace swba::apps
{
namespace
{
constexpr double kPi = 3.14159265358979323846;

std::string trim(const std::string& s)
{
	const auto b = s.find_first_not_of(" \t\r\n");
	if (b == std::string::npos) return "";
	const auto e = s.find_last_not_of(" \t\r\n");
	return s.substr(b, e - b + 1);
}

std::string lower(std::string s)
{
	std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
	return s;
}

double parse_double(const std::string& v)
{
	std::size_t pos = 0;
	double d = 0;
	try
	{
		d = std::stod(v, &pos);
	}
	catch (const std::exception&)
	{
		throw std::invalid_argument("'" + v + "' is not a number");
	}
	if (pos != v.size()) throw std::invalid_argument("'" + v + "' is not a number");
	if (!std::isfinite(d)) throw std::invalid_argument("'" + v + "' is not finite");
	return d;
}

long long parse_integer(const std::string& v)
{
	std::size_t pos = 0;
	long long i = 0;
	try
	{
		i = std::stoll(v, &pos);
	}
	catch (const std::exception&)
	{
		throw std::invalid_argument("'" + v + "' is not an integer");
	}
	if (pos != v.size()) throw std::invalid_argument("'" + v + "' is not an integer");
	return i;
}

int parse_int_min(const std::string& v, long long min_value)
{
	const long long i = parse_integer(v);
	if (i < min_value || i > std::numeric_limits<int>::max())
		throw std::invalid_argument("'" + v + "' must be an integer >= " + std::to_string(min_value));
	return static_cast<int>(i);
}

bool parse_bool(const std::string& v)
{
	const std::string l = lower(v);
	if (l == "true" || l == "1" || l == "yes" || l == "on") return true;
	if (l == "false" || l == "0" || l == "no" || l == "off") return false;
	throw std::invalid_argument("'" + v + "' is not a boolean (true/false, 1/0, yes/no, on/off)");
}

double parse_positive(const std::string& v)
{
	const double d = parse_double(v);
	if (!(d > 0)) throw std::invalid_argument("'" + v + "' must be > 0");
	return d;
}

double parse_non_negative(const std::string& v)
{
	const double d = parse_double(v);
	if (d < 0) throw std::invalid_argument("'" + v + "' must be >= 0");
	return d;
}

std::string format_double(double v)
{
	char buf[64];
	if (v == std::floor(v) && std::abs(v) < 1e15)
	{
		std::snprintf(buf, sizeof(buf), "%.0f", v);
		return buf;
	}
	std::snprintf(buf, sizeof(buf), "%.17g", v);
	// Shortest representation that reads back exactly.
	for (int p = 1; p <= 17; p++)
	{
		char b2[64];
		std::snprintf(b2, sizeof(b2), "%.*g", p, v);
		if (std::stod(b2) == v) return b2;
	}
	return buf;
}

std::string bool_text(bool b) { return b ? "true" : "false"; }

std::string join(const std::vector<std::string>& items, const std::string& sep)
{
	std::string s;
	for (std::size_t i = 0; i < items.size(); i++) s += (i ? sep : "") + items[i];
	return s;
}

std::string policies_text(const std::vector<estimators::LandmarkPolicy>& p)
{
	if (p.size() == 2) return "both";
	return p.empty() ? "" : to_string(p.front());
}

std::string fej_text(const std::vector<bool>& f)
{
	if (f.size() == 2) return "both";
	return f.empty() ? "" : (f.front() ? "on" : "off");
}

std::string windows_text(const std::vector<int>& w)
{
	std::vector<std::string> s;
	for (int x : w) s.push_back(std::to_string(x));
	return join(s, ",");
}

/** Sensor std: ≤ 0 in the options means "the observation's own" (written as 0). */
std::string std_deg_text(double rad) { return format_double(rad > 0 ? rad * 180.0 / kPi : 0.0); }
}  // namespace

// ----------------------------------------------------------------------------------------------
const std::vector<RunConfigKey>& run_config_key_table()
{
	using S = std::string;
	static const std::vector<RunConfigKey> table = {
		{"run", "rawlog", "path", "rawlog to run on; empty = kf-slam_6D_demo.rawlog of mrpt-common",
		 [](const S& v, RunOptions& o) { o.rawlog = v; }, [](const RunOptions& o) { return o.rawlog; }},
		{"run", "ground_truth", "path",
		 "MRPT ground-truth robot path; empty = <rawlog name>_ground_truth_robot_path.txt next to the rawlog if present",
		 [](const S& v, RunOptions& o) { o.ground_truth = v; }, [](const RunOptions& o) { return o.ground_truth; }},
		{"run", "out_dir", "path", "output directory (created)",
		 [](const S& v, RunOptions& o) {
			 if (v.empty()) throw std::invalid_argument("must not be empty");
			 o.out_dir = v;
		 },
		 [](const RunOptions& o) { return o.out_dir; }},
		{"run", "max_steps", "steps", "process at most this many steps; 0 = all",
		 [](const S& v, RunOptions& o) { o.max_steps = static_cast<std::size_t>(parse_int_min(v, 0)); },
		 [](const RunOptions& o) { return std::to_string(o.max_steps); }},
		{"run", "threads", "count", "solver threads (evaluation and assembly)",
		 [](const S& v, RunOptions& o) { o.threads = parse_int_min(v, 1); },
		 [](const RunOptions& o) { return std::to_string(o.threads); }},
		{"run", "batch", "bool", "run the batch estimator (all factors, one solve: window = infinity)",
		 [](const S& v, RunOptions& o) { o.run_batch = parse_bool(v); },
		 [](const RunOptions& o) { return bool_text(o.run_batch); }},
		{"run", "batch_max_iterations", "iterations", "LM iteration limit of the batch solve",
		 [](const S& v, RunOptions& o) { o.batch_max_iterations = parse_int_min(v, 1); },
		 [](const RunOptions& o) { return std::to_string(o.batch_max_iterations); }},
		{"run", "causal", "bool",
		 "also run the full-history causal optimum (online, W = infinity; re-solves the whole history every step)",
		 [](const S& v, RunOptions& o) { o.run_causal = parse_bool(v); },
		 [](const RunOptions& o) { return bool_text(o.run_causal); }},
		{"run", "plots", "bool", "write gnuplot plots (only when gnuplot is found)",
		 [](const S& v, RunOptions& o) { o.plots = parse_bool(v); },
		 [](const RunOptions& o) { return bool_text(o.plots); }},
		{"run", "progress", "bool", "progress lines on stderr for estimators running longer than a second",
		 [](const S& v, RunOptions& o) { o.progress = parse_bool(v); },
		 [](const RunOptions& o) { return bool_text(o.progress); }},

		{"window", "sizes", "poses", "window sizes W, comma-separated, each >= 2",
		 [](const S& v, RunOptions& o) { o.windows = parse_window_list(v, "sizes"); },
		 [](const RunOptions& o) { return windows_text(o.windows); }},
		{"window", "policy", "slam|constant-time|both",
		 "landmark policy: slam keeps every landmark, constant-time marginalises landmarks no window pose sees",
		 [](const S& v, RunOptions& o) { o.policies = parse_policy_list(v); },
		 [](const RunOptions& o) { return policies_text(o.policies); }},
		{"window", "fej", "on|off|both", "first-estimate Jacobians for factors touching the marginal prior",
		 [](const S& v, RunOptions& o) { o.fej = parse_fej_list(v); },
		 [](const RunOptions& o) { return fej_text(o.fej); }},
		{"window", "landmarks", "inverse-depth|xyz", "landmark parameterisation",
		 [](const S& v, RunOptions& o) { o.window.landmarks = estimators::parse_landmark_parameterization(v); },
		 [](const RunOptions& o) { return to_string(o.window.landmarks); }},
		{"window", "gauge", "fixed|free|prior", "gauge: first pose fixed, free, or an SE(3) prior on it",
		 [](const S& v, RunOptions& o) { o.window.gauge = parse_gauge_mode(v); },
		 [](const RunOptions& o) { return to_string(o.window.gauge); }},
		{"window", "gauge_prior_weight", "1/(m^2 or rad^2)", "information of the gauge prior (gauge = prior only)",
		 [](const S& v, RunOptions& o) { o.window.gauge_prior_weight = parse_positive(v); },
		 [](const RunOptions& o) { return format_double(o.window.gauge_prior_weight); }},
		{"window", "marginalization_threshold", "relative", "relative eigenvalue cut of the marginal prior, in [0, 1)",
		 [](const S& v, RunOptions& o) {
			 const double d = parse_non_negative(v);
			 if (!(d < 1)) throw std::invalid_argument("'" + v + "' must be < 1");
			 o.window.marginalization_threshold = d;
		 },
		 [](const RunOptions& o) { return format_double(o.window.marginalization_threshold); }},

		{"solver", "max_iterations", "iterations", "LM iterations per window step",
		 [](const S& v, RunOptions& o) { o.window.solver.max_iterations = parse_int_min(v, 1); },
		 [](const RunOptions& o) { return std::to_string(o.window.solver.max_iterations); }},
		{"solver", "function_tolerance", "relative", "stop when |d cost| / cost < this",
		 [](const S& v, RunOptions& o) { o.window.solver.function_tolerance = parse_non_negative(v); },
		 [](const RunOptions& o) { return format_double(o.window.solver.function_tolerance); }},
		{"solver", "gradient_tolerance", "cost units", "stop when max |gradient| <= this",
		 [](const S& v, RunOptions& o) { o.window.solver.gradient_tolerance = parse_non_negative(v); },
		 [](const RunOptions& o) { return format_double(o.window.solver.gradient_tolerance); }},
		{"solver", "parameter_tolerance", "relative", "stop when |step| <= this * (|x| + this)",
		 [](const S& v, RunOptions& o) { o.window.solver.parameter_tolerance = parse_non_negative(v); },
		 [](const RunOptions& o) { return format_double(o.window.solver.parameter_tolerance); }},
		{"solver", "linear_solver", "auto|dense-schur|sparse-schur|dense-normal|sparse-normal",
		 "linear solver of each LM step",
		 [](const S& v, RunOptions& o) { o.window.solver.linear_solver = parse_linear_solver(v); },
		 [](const RunOptions& o) { return to_string(o.window.solver.linear_solver); }},
		{"solver", "dense_max_dim", "unknowns", "with linear_solver = auto: reduced systems up to this size use dense LDLT",
		 [](const S& v, RunOptions& o) { o.window.solver.dense_max_dim = parse_int_min(v, 0); },
		 [](const RunOptions& o) { return std::to_string(o.window.solver.dense_max_dim); }},

		{"ekf", "enabled", "bool", "run MRPT's EKF (CRangeBearingKFSLAM) with each method",
		 [](const S& v, RunOptions& o) { o.run_ekf = parse_bool(v); },
		 [](const RunOptions& o) { return bool_text(o.run_ekf); }},
		{"ekf", "methods", "names", "comma-separated: kfEKFNaive, kfEKFAlaDavison, kfIKFFull, kfIKF",
		 [](const S& v, RunOptions& o) { o.ekf_methods = parse_ekf_method_list(v); },
		 [](const RunOptions& o) { return join(o.ekf_methods, ","); }},
		{"ekf", "ini_file", "path",
		 "optional kf-slam INI for the EKF's other options; empty = MRPT's defaults (the sensor noise is always the [sensor] one)",
		 [](const S& v, RunOptions& o) { o.ekf_ini = v; }, [](const RunOptions& o) { return o.ekf_ini; }},

		{"sensor", "std_range_m", "m", "range noise for every estimator; 0 = the observation's own sensor_std_range",
		 [](const S& v, RunOptions& o) { o.window.sensor_std_range = parse_non_negative(v); },
		 [](const RunOptions& o) { return format_double(std::max(0.0, o.window.sensor_std_range)); }},
		{"sensor", "std_yaw_deg", "deg", "yaw noise for every estimator; 0 = the observation's own sensor_std_yaw",
		 [](const S& v, RunOptions& o) { o.window.sensor_std_yaw = parse_non_negative(v) * kPi / 180.0; },
		 [](const RunOptions& o) { return std_deg_text(o.window.sensor_std_yaw); }},
		{"sensor", "std_pitch_deg", "deg", "pitch noise for every estimator; 0 = the observation's own sensor_std_pitch",
		 [](const S& v, RunOptions& o) { o.window.sensor_std_pitch = parse_non_negative(v) * kPi / 180.0; },
		 [](const RunOptions& o) { return std_deg_text(o.window.sensor_std_pitch); }},

		{"odometry", "min_sigma_translation_m", "m", "floor of the odometry's translational standard deviations",
		 [](const S& v, RunOptions& o) { o.window.odometry.min_sigma_translation = parse_positive(v); },
		 [](const RunOptions& o) { return format_double(o.window.odometry.min_sigma_translation); }},
		{"odometry", "min_sigma_rotation_rad", "rad", "floor of the odometry's rotational standard deviations",
		 [](const S& v, RunOptions& o) { o.window.odometry.min_sigma_rotation = parse_positive(v); },
		 [](const RunOptions& o) { return format_double(o.window.odometry.min_sigma_rotation); }},
	};
	return table;
}

const std::vector<std::string>& run_config_keys()
{
	static const std::vector<std::string> keys = [] {
		std::vector<std::string> k;
		const RunOptions defaults;
		for (const auto& e : run_config_key_table())
			k.push_back(e.section + "." + e.key + " [" + e.unit + "]: " + e.meaning + " (Default=" + e.get(defaults) + ")");
		return k;
	}();
	return keys;
}

std::string format_run_config(const RunOptions& options)
{
	std::string s;
	std::string section;
	for (const auto& e : run_config_key_table())
	{
		if (e.section != section)
		{
			s += (section.empty() ? "" : "\n") + std::string("[") + e.section + "]\n";
			section = e.section;
		}
		s += e.key + " = " + e.get(options) + "\n";
	}
	return s;
}

namespace
{
void apply_config(const mrpt::config::CConfigFileBase& cfg, const std::string& source, RunOptions& options)
{
	const auto& table = run_config_key_table();
	std::vector<std::string> known_sections;
	for (const auto& e : table)
		if (std::find(known_sections.begin(), known_sections.end(), e.section) == known_sections.end())
			known_sections.push_back(e.section);

	std::vector<std::string> sections;
	cfg.getAllSections(sections);
	for (const auto& section : sections)
	{
		if (trim(section).empty()) continue;  // keys before any section header
		if (std::find(known_sections.begin(), known_sections.end(), section) == known_sections.end())
			throw std::runtime_error("config '" + source + "': unknown section [" + section +
									 "] (known sections: " + join(known_sections, ", ") + ")");
		std::vector<std::string> keys;
		cfg.getAllKeys(section, keys);
		for (const auto& key : keys)
		{
			auto it = std::find_if(table.begin(), table.end(),
								   [&](const RunConfigKey& e) { return e.section == section && e.key == key; });
			if (it == table.end())
			{
				std::vector<std::string> known;
				for (const auto& e : table)
					if (e.section == section) known.push_back(e.key);
				throw std::runtime_error("config '" + source + "': unknown key '" + key + "' in section [" + section +
										 "] (known keys: " + join(known, ", ") + ")");
			}
			std::string value = cfg.read_string(section, key, "");
			// MRPT keeps trailing "// comments" in some cases: drop them.
			const auto comment = value.find("//");
			if (comment != std::string::npos) value = value.substr(0, comment);
			value = trim(value);
			try
			{
				it->set(value, options);
			}
			catch (const std::exception& e)
			{
				throw std::runtime_error("config '" + source + "': [" + section + "] " + key + ": " + e.what());
			}
		}
	}
}
}  // namespace

void load_run_config(const std::string& path, RunOptions& options)
{
	if (!mrpt::system::fileExists(path)) throw std::runtime_error("config '" + path + "': file does not exist");
	mrpt::config::CConfigFile cfg(path);
	apply_config(cfg, path, options);
}

void load_run_config_text(const std::string& text, const std::string& source_name, RunOptions& options)
{
	mrpt::config::CConfigFileMemory cfg(text);
	apply_config(cfg, source_name, options);
}

// ----------------------------------------------------------------------------------------------
std::vector<std::string> split_list(const std::string& text, const std::string& what)
{
	std::vector<std::string> items;
	std::string cur;
	std::istringstream in(text);
	while (std::getline(in, cur, ','))
	{
		cur = trim(cur);
		if (cur.empty()) throw std::invalid_argument(what + ": empty item in '" + text + "'");
		items.push_back(cur);
	}
	if (!text.empty() && text.back() == ',') throw std::invalid_argument(what + ": empty item in '" + text + "'");
	if (items.empty()) throw std::invalid_argument(what + ": empty list");
	return items;
}

std::vector<int> parse_window_list(const std::string& text, const std::string& what)
{
	std::vector<int> w;
	for (const auto& item : split_list(text, what))
	{
		long long v = 0;
		try
		{
			v = parse_integer(item);
		}
		catch (const std::exception&)
		{
			throw std::invalid_argument(what + ": '" + item + "' is not an integer window size");
		}
		if (v < 2 || v > 1000000)
			throw std::invalid_argument(what + ": window size must be >= 2, got " + item);
		if (std::find(w.begin(), w.end(), static_cast<int>(v)) == w.end()) w.push_back(static_cast<int>(v));
	}
	return w;
}

std::vector<estimators::LandmarkPolicy> parse_policy_list(const std::string& text)
{
	const std::string t = trim(text);
	if (t == "both") return {estimators::LandmarkPolicy::Slam, estimators::LandmarkPolicy::ConstantTime};
	try
	{
		return {estimators::parse_landmark_policy(t)};
	}
	catch (const std::exception&)
	{
		throw std::invalid_argument("unknown policy '" + t + "' (expected slam, constant-time or both)");
	}
}

std::vector<bool> parse_fej_list(const std::string& text)
{
	const std::string t = lower(trim(text));
	if (t == "both") return {true, false};
	try
	{
		return {parse_bool(t)};
	}
	catch (const std::exception&)
	{
		throw std::invalid_argument("unknown fej value '" + text + "' (expected on, off or both)");
	}
}

std::vector<std::string> parse_ekf_method_list(const std::string& text)
{
	static const char* names[] = {"kfEKFNaive", "kfEKFAlaDavison", "kfIKFFull", "kfIKF"};
	std::vector<std::string> m;
	for (const auto& item : split_list(text, "EKF methods"))
	{
		const std::string name = names[estimators::ekf_method_from_name(item)];
		if (std::find(m.begin(), m.end(), name) == m.end()) m.push_back(name);
	}
	return m;
}

void RunOptions::validate() const
{
	if (windows.empty() && !run_ekf && !run_batch && !run_causal)
		throw std::invalid_argument("nothing to run (no window sizes, --no-ekf and --no-batch)");
	for (int w : windows)
		if (w < 2) throw std::invalid_argument("window size must be >= 2, got " + std::to_string(w));
	if (policies.empty()) throw std::invalid_argument("no landmark policy");
	if (fej.empty()) throw std::invalid_argument("no FEJ setting");
	if (run_ekf && ekf_methods.empty()) throw std::invalid_argument("no EKF method");
	for (const auto& m : ekf_methods) estimators::ekf_method_from_name(m);
	if (threads < 1) throw std::invalid_argument("threads must be >= 1");
	if (batch_max_iterations < 1) throw std::invalid_argument("batch_max_iterations must be >= 1");
	if (out_dir.empty()) throw std::invalid_argument("output directory must not be empty");
	estimators::SlidingWindowOptions w = window;
	w.window_size = windows.empty() ? 0 : windows.front();
	w.validate();
}
}  // namespace swba::apps

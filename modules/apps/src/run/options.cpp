#include <swba/estimators/ekf_slam.h>
#include <swba/apps/run_options.h>
#include <swba/core/file.h>
#include <swba/core/validation.h>

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/system/filesystem.h>

#include <algorithm>
#include <cctype>
#include <map>
#include <sstream>
#include <stdexcept>

namespace swba::apps
{
namespace
{
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

std::string join(const std::vector<std::string>& items, const std::string& sep)
{
	std::string s;
	for (std::size_t i = 0; i < items.size(); i++) s += (i ? sep : "") + items[i];
	return s;
}

std::string policies_text(const std::vector<estimators::LandmarkPolicy>& p)
{
	std::vector<std::string> names;
	for (const auto policy : p) names.push_back(to_string(policy));
	return join(names, ",");
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

using S = std::string;
using O = RunOptions;

/** [run]: what to run on, where the output goes, which estimators run besides the windows. */
IniKeys<RunOptions> run_section_keys()
{
	using namespace ini;
	return {
		text_key<O>("run", "rawlog", "path", "rawlog to run on; empty = kf-slam_6D_demo.rawlog of mrpt-common",
					&O::rawlog),
		text_key<O>("run", "ground_truth", "path",
					"MRPT ground-truth robot path; empty = <rawlog name>_ground_truth_robot_path.txt next to the "
					"rawlog if present",
					&O::ground_truth),
		text_key<O>("run", "association_truth", "path",
					"rawlog with the same readings and their landmark IDs, the truth of the association of a rawlog "
					"without IDs; empty = the simulator's landmark file next to the rawlog, if present",
					&O::association_truth),
		{"run", "out_dir", "path", "output directory (created)",
		 [](const S& v, O& o) {
			 if (v.empty()) throw std::invalid_argument("must not be empty");
			 o.out_dir = v;
		 },
		 [](const O& o) { return o.out_dir; }},
		int_key<O>("run", "max_steps", "steps", "process at most this many steps; 0 = all", &O::max_steps, 0),
		bool_key<O>("run", "batch", "run the batch estimator (all factors, one solve: window = infinity)",
					&O::run_batch),
		int_key<O>("run", "batch_max_iterations", "iterations", "LM iteration limit of the batch solve",
				   &O::batch_max_iterations, 1),
		bool_key<O>("run", "causal",
					"also run the full-history causal optimum (online, W = infinity; re-solves the whole history "
					"every step)",
					&O::run_causal),
		bool_key<O>("run", "plots", "write gnuplot plots (only when gnuplot is found)", &O::plots),
		bool_key<O>("run", "progress", "progress lines on stderr for estimators running longer than a second",
					&O::progress),
		bool_key<O>("run", "verbose", "each solve's summary on stderr (a line per window step, the batch's full report)",
					&O::verbose),
	};
}

/** The run's sweep over window settings, in [window] beside the window's own keys. */
IniKeys<RunOptions> window_sweep_keys()
{
	return {
		{"window", "sizes", "poses", "window sizes W, comma-separated, each >= 2",
		 [](const S& v, O& o) { o.windows = parse_window_list(v, ""); },  // the key is already in the message
		 [](const O& o) { return windows_text(o.windows); }},
		{"window", "policy", "slam|constant-time|map, a comma-separated list, both or all",
		 "landmark policy: slam keeps every landmark, constant-time marginalises landmarks no window pose sees, "
		 "map does too and keeps their marginals for when they are seen again",
		 [](const S& v, O& o) { o.policies = parse_policy_list(v); },
		 [](const O& o) { return policies_text(o.policies); }},
		{"window", "fej", "on|off|both", "first-estimate Jacobians for factors touching the marginal prior",
		 [](const S& v, O& o) { o.fej = parse_fej_list(v); }, [](const O& o) { return fej_text(o.fej); }},
	};
}

/** [ekf]: MRPT's filter as the peer, once per method. */
IniKeys<RunOptions> ekf_keys()
{
	return {
		ini::bool_key<O>("ekf", "enabled", "run MRPT's EKF (CRangeBearingKFSLAM) with each method", &O::run_ekf),
		{"ekf", "methods", "names",
		 "comma-separated: kfEKFNaive, kfEKFAlaDavison, kfIKFFull (MRPT's kfIKF is refused: it throws at its first "
		 "update)",
		 [](const S& v, O& o) { o.ekf_methods = parse_ekf_method_list(v); },
		 [](const O& o) { return join(o.ekf_methods, ","); }},
		{"ekf", "ini_file", "path",
		 "optional kf-slam INI for the EKF's other options; empty = MRPT's defaults (the sensor noise is always the "
		 "[sensor] one)",
		 [](const S& v, O& o) { o.ekf_ini = v; }, [](const O& o) { return o.ekf_ini; }},
	};
}

IniKeys<RunOptions> make_key_table()
{
	IniKeys<RunOptions> t = run_section_keys();
	for (auto& k : window_sweep_keys()) t.push_back(std::move(k));
	append_keys(t, estimators::SlidingWindowOptions::ini_keys("window"), [](auto& o) -> auto& { return o.window; });
	append_keys(t, SolverOptions::ini_keys("solver"), [](auto& o) -> auto& { return o.window.solver; });
	for (auto& k : ekf_keys()) t.push_back(std::move(k));
	append_keys(t, estimators::SensorNoiseOptions::ini_keys("sensor"), [](auto& o) -> auto& { return o.window.sensor; });
	append_keys(t, io::OdometryInformationOptions::ini_keys("odometry"),
				[](auto& o) -> auto& { return o.window.odometry; });
	append_keys(t, io::SensorRoles::ini_keys("sensors"), [](auto& o) -> auto& { return o.sensors; });
	append_keys(t, estimators::InertialWindowOptions::ini_keys("inertial"), [](auto& o) -> auto& { return o.inertial; });
	append_keys(t, ImuNoise::ini_keys("imu"), [](auto& o) -> auto& { return o.inertial.measurements.noise; });
	return t;
}
}  // namespace

const IniKeys<RunOptions>& run_config_key_table()
{
	static const IniKeys<RunOptions> table = make_key_table();
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
	std::size_t known_found = 0;
	for (const auto& section : sections)
	{
		if (trim(section).empty())
		{
			std::vector<std::string> keys;
			cfg.getAllKeys(section, keys);
			if (!keys.empty())
				throw std::runtime_error("config '" + source + "': key '" + keys.front() + "' before any [section]");
			continue;
		}
		known_found++;
		if (std::find(known_sections.begin(), known_sections.end(), section) == known_sections.end())
			throw std::runtime_error("config '" + source + "': unknown section [" + section +
									 "] (known sections: " + join(known_sections, ", ") + ")");
		std::vector<std::string> keys;
		cfg.getAllKeys(section, keys);
		for (const auto& key : keys)
		{
			auto it = std::find_if(table.begin(), table.end(),
								   [&](const IniKey<RunOptions>& e) { return e.section == section && e.key == key; });
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
	// An empty file (or one of comments only) is almost always the wrong file: say so.
	if (known_found == 0)
		throw std::runtime_error("config '" + source + "': no section (expected some of [" + join(known_sections, "], [") + "])");
}
}  // namespace

void load_run_config(const std::string& path, RunOptions& options)
{
	load_run_config_text(read_text_file(path, "config"), path, options);
}

namespace
{
/** MRPT's parser skips a line it cannot read, and of a key given twice in a section keeps the last; here
 * either is an error (an option silently left at its default, or set by a line the user may not see). */
void check_config_lines(const std::string& text, const std::string& source)
{
	std::istringstream in(text);
	std::size_t n = 0;
	std::string section;
	std::map<std::pair<std::string, std::string>, std::size_t> first_line;  // (section, key) -> line
	for (std::string line; std::getline(in, line);)
	{
		n++;
		const std::string t = trim(line);
		if (t.empty() || t[0] == '#' || t[0] == ';' || t.rfind("//", 0) == 0) continue;
		const std::string at = "config '" + source + "':" + std::to_string(n) + ": ";
		if (t.front() == '[' && t.back() == ']')
		{
			section = trim(t.substr(1, t.size() - 2));
			continue;
		}
		const auto eq = t.find('=');
		if (eq == std::string::npos)
			throw std::runtime_error(at + "'" + t + "' is neither a [section], a key = value line nor a comment");
		const std::string key = trim(t.substr(0, eq));
		const auto [it, fresh] = first_line.emplace(std::make_pair(lower(section), lower(key)), n);
		if (!fresh)
			throw std::runtime_error(at + "[" + section + "] " + key + " is given twice (first on line " +
									 std::to_string(it->second) + ")");
	}
}
}  // namespace

void load_run_config_text(const std::string& text, const std::string& source_name, RunOptions& options)
{
	check_config_lines(text, source_name);
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
	const std::string at = what.empty() ? "" : what + ": ";
	std::vector<int> w;
	for (const auto& item : split_list(text, what.empty() ? "window sizes" : what))
	{
		const auto out_of_range = [&] {
			return std::invalid_argument(at + "window size must be in [2, " + std::to_string(kMaxWindowSize) +
										 "], got " + item);
		};
		long long v = 0;
		try
		{
			v = ini::parse_integer(item);
		}
		catch (const std::exception&)
		{
			// Digits that overflow a long long are an integer out of range, not a non-integer.
			const std::size_t d = (item[0] == '-' || item[0] == '+') ? 1 : 0;
			if (item.size() > d && item.find_first_not_of("0123456789", d) == std::string::npos) throw out_of_range();
			throw std::invalid_argument(at + "'" + item + "' is not an integer window size");
		}
		if (v < 2 || v > kMaxWindowSize) throw out_of_range();
		if (std::find(w.begin(), w.end(), static_cast<int>(v)) == w.end()) w.push_back(static_cast<int>(v));
	}
	return w;
}

std::vector<estimators::LandmarkPolicy> parse_policy_list(const std::string& text)
{
	using estimators::LandmarkPolicy;
	const std::string t = trim(text);
	if (t == "both") return {LandmarkPolicy::Slam, LandmarkPolicy::ConstantTime};
	if (t == "all") return {LandmarkPolicy::Slam, LandmarkPolicy::ConstantTime, LandmarkPolicy::Map};
	std::vector<LandmarkPolicy> out;
	for (const auto& item : split_list(t, "policies"))
	{
		LandmarkPolicy p;
		try
		{
			p = estimators::parse_landmark_policy(item);
		}
		catch (const std::exception&)
		{
			throw std::invalid_argument("unknown policy '" + item +
										"' (expected slam, constant-time, map, a comma-separated list of them, both or all)");
		}
		if (std::find(out.begin(), out.end(), p) == out.end()) out.push_back(p);
	}
	return out;
}

std::vector<bool> parse_fej_list(const std::string& text)
{
	const std::string t = lower(trim(text));
	if (t == "both") return {true, false};
	try
	{
		return {ini::parse_bool(t)};
	}
	catch (const std::exception&)
	{
		throw std::invalid_argument("unknown fej value '" + text + "' (expected on, off or both)");
	}
}

std::vector<std::string> parse_ekf_method_list(const std::string& text)
{
	static const char* names[] = {"kfEKFNaive", "kfEKFAlaDavison", "kfIKFFull"};
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
	if (batch_max_iterations < 1) throw std::invalid_argument("batch_max_iterations must be >= 1");
	if (out_dir.empty()) throw std::invalid_argument("output directory must not be empty");
	estimators::SlidingWindowOptions w = window;
	w.window_size = windows.empty() ? 0 : windows.front();
	for (const auto policy : policies)  // a policy may reject the other options (map: the free gauge)
	{
		w.policy = policy;
		w.validate();
	}
	validate_with_prefix(inertial.measurements.noise, "[imu]: ");
	validate_with_prefix(inertial, "[inertial]: ");
	validate_with_prefix(sensors, "[sensors]: ");
}
}  // namespace swba::apps

// Command-line parsing over MRPT's TCLAP, with the conventions TCLAP lacks: "--name=value", and an
// error for an option no argument declares (TCLAP would hand "--bogus" to an optional positional).
#include "cli.h"

#include <mrpt/version.h>
#include <swba/linear/rank_update.h>

#include <Eigen/Core>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>
#include <vector>

namespace swba::app
{
namespace
{
/** TCLAP's own arguments (listed last by --help). */
bool is_builtin(const TCLAP::Arg* a)
{
	const std::string& n = a->getName();
	return n == "ignore_rest" || n == "version" || n == "help";
}

/** The arguments in the order --help lists them: the positional ones, then the options in the order the
 * command adds them (input, main choices, tuning, output, verbosity), then TCLAP's own. TCLAP keeps
 * positional arguments in order at the end of its list and options in reverse order of addition. */
std::vector<TCLAP::Arg*> help_order(TCLAP::CmdLineInterface& c)
{
	std::vector<TCLAP::Arg*> positional, options, builtin;
	for (TCLAP::Arg* a : c.getArgList())
	{
		if (is_builtin(a))
			builtin.push_back(a);
		else if (a->longID().compare(0, 1, "<") == 0)
			positional.push_back(a);
		else
			options.insert(options.begin(), a);
	}
	std::vector<TCLAP::Arg*> all = positional;
	all.insert(all.end(), options.begin(), options.end());
	all.insert(all.end(), builtin.begin(), builtin.end());
	return all;
}

class OneLineOutput : public TCLAP::StdOutput
{
   public:
	/** The line of `swba version` (TCLAP's own reads "swba run  version: 0.1.0"). */
	void version(TCLAP::CmdLineInterface&) override { std::cout << version_line() << "\n"; }
	bool failed = false;
	std::string extra_argument_hint;  ///< said after "unexpected argument 'x'"
	/** TCLAP's layout, in help_order. */
	void usage(TCLAP::CmdLineInterface& c) override
	{
		const std::vector<TCLAP::Arg*> args = help_order(c);
		std::string s = c.getProgramName() + " ";
		for (const TCLAP::Arg* a : args)
			s += " " + (a->longID().compare(0, 1, "<") == 0 && !a->isRequired() ? "[" + a->shortID() + "]" : a->shortID());
		const int offset = std::min(static_cast<int>(c.getProgramName().size()) + 2, 75 / 2);
		m_my_output << "\nUSAGE: \n\n";
		spacePrint(m_my_output, s, 75, 3, offset);
		m_my_output << "\n\nWhere: \n\n";
		for (const TCLAP::Arg* a : args)
		{
			spacePrint(m_my_output, a->longID(), 75, 3, 3);
			spacePrint(m_my_output, a->getDescription(), 75, 5, 0);
			m_my_output << "\n";
		}
		m_my_output << "\n";
		spacePrint(m_my_output, c.getMessage(), 75, 3, 0);
		m_my_output << "\n";
	}
	void failure(TCLAP::CmdLineInterface& c, TCLAP::ArgException& e) override
	{
		failed = true;
		std::string missing;  // TCLAP names no unlabeled argument in its "required arguments missing"
		for (const TCLAP::Arg* a : c.getArgList())
			if (a->isRequired() && !a->isSet()) missing += (missing.empty() ? "" : ", ") + a->getName();
		std::cerr << c.getProgramName() << ": error: ";
		const std::string tclap_id = "Argument: ";
		if (!missing.empty() && e.error().find("required arguments missing") != std::string::npos)
			std::cerr << "missing argument(s): " << missing;
		else if (e.error().find("Argument already set!") != std::string::npos &&
				 e.argId().compare(0, tclap_id.size(), tclap_id) == 0)
		{
			// TCLAP's "Argument: (--name)" or "Argument: (-f, --name)".
			std::string id = e.argId().substr(tclap_id.size());
			if (id.size() > 2 && id.front() == '(' && id.back() == ')') id = id.substr(1, id.size() - 2);
			std::cerr << "option " << id << " given twice";
		}
		else if (e.error().find("Couldn't find match for argument") != std::string::npos &&
				 e.argId().compare(0, tclap_id.size(), tclap_id) == 0)
		{
			// A word no positional argument takes: name it, and what to do instead when the command knows.
			std::cerr << "unexpected argument '" << e.argId().substr(tclap_id.size()) << "'";
			if (!extra_argument_hint.empty()) std::cerr << ": " << extra_argument_hint;
		}
		else
		{
			std::cerr << e.error();
			if (e.argId().find_first_not_of(' ') != std::string::npos) std::cerr << " [" << e.argId() << "]";
		}
		std::cerr << " (see --help)\n";
	}
};

bool is_number(const std::string& s)
{
	char* end = nullptr;
	std::strtod(s.c_str(), &end);
	return !s.empty() && end == s.c_str() + s.size();
}

/** The argument of `cmd` that `option` ("--name" or "-f") names, or null. */
TCLAP::Arg* find_option(TCLAP::CmdLine& cmd, const std::string& option)
{
	for (TCLAP::Arg* a : cmd.getArgList())
	{
		if (option.size() > 2 && option.compare(0, 2, "--") == 0 && a->getName() == option.substr(2)) return a;
		if (option.size() == 2 && !a->getFlag().empty() && a->getFlag() == option.substr(1)) return a;
	}
	return nullptr;
}

/** Whether `option` ("-as") is a run of single-letter switches of `cmd` (TCLAP accepts those). */
bool is_switch_run(TCLAP::CmdLine& cmd, const std::string& option)
{
	for (std::size_t i = 1; i < option.size(); i++)
	{
		const TCLAP::Arg* a = find_option(cmd, std::string("-") + option[i]);
		if (!a || a->isValueRequired()) return false;
	}
	return true;
}

/** argv with "--name=value" split in two and evo's "--name_with_underscores" read as
 * "--name-with-underscores"; an unknown option, or a value given to a switch, is an error message instead. An argument after a value-taking option is its value even if it starts
 * with '-' (a negative offset); after "--" nothing is an option. */
std::string normalise(TCLAP::CmdLine& cmd, int argc, char** argv, std::vector<std::string>& out)
{
	out.assign(argv, argv + std::min(argc, 1));
	bool rest = false;
	for (int i = 1; i < argc; i++)
	{
		std::string a = argv[i];
		if (rest || a.size() < 2 || a[0] != '-' || is_number(a))
		{
			out.push_back(a);
			continue;
		}
		if (a == "--")
		{
			rest = true;
			out.push_back(a);
			continue;
		}
		std::string value;
		const std::size_t eq = a.compare(0, 2, "--") == 0 ? a.find('=') : std::string::npos;
		if (eq != std::string::npos)
		{
			value = a.substr(eq + 1);
			a.resize(eq);
		}
		const TCLAP::Arg* arg = find_option(cmd, a);
		if (!arg && a.compare(0, 2, "--") == 0 && a.find('_') != std::string::npos)
		{
			// evo's spelling of the same option (--t_max_diff for --t-max-diff).
			std::string dashed = a;
			std::replace(dashed.begin() + 2, dashed.end(), '_', '-');
			if ((arg = find_option(cmd, dashed))) a = dashed;
		}
		if (!arg && a.size() > 2 && a[1] != '-' && is_switch_run(cmd, a))
		{
			out.push_back(a);
			continue;
		}
		if (!arg) return "unknown option '" + a + "'";
		out.push_back(a);
		if (eq != std::string::npos)
		{
			if (!arg->isValueRequired()) return "option '" + a + "' takes no value";
			out.push_back(value);
		}
		else if (arg->isValueRequired() && i + 1 < argc)
			out.push_back(argv[++i]);
	}
	return "";
}
}  // namespace

std::string version_line()
{
	std::ostringstream s;
	s << "swba 0.1.0 (MRPT " << ((MRPT_VERSION >> 8) & 0xF) << "." << ((MRPT_VERSION >> 4) & 0xF) << "."
	  << (MRPT_VERSION & 0xF) << ", Eigen " << EIGEN_WORLD_VERSION << "." << EIGEN_MAJOR_VERSION << "."
	  << EIGEN_MINOR_VERSION << "; rank-update kernel " << enum_name(active_simd_level()) << ")";
	return s.str();
}

std::string share_dir()
{
	namespace fs = std::filesystem;
	std::error_code ec;
	const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
	if (!ec && exe.parent_path().filename() == fs::path(SWBA_INSTALL_BINDIR).filename())
	{
		const fs::path installed = exe.parent_path().parent_path() / SWBA_INSTALL_SHAREDIR;
		if (fs::is_directory(installed, ec)) return installed.string();
	}
	return SWBA_SHARE_DIR;
}

std::optional<int> parse_command_line(TCLAP::CmdLine& cmd, int argc, char** argv,
									  const std::string& extra_argument_hint)
{
	std::vector<std::string> args;
	const std::string error = normalise(cmd, argc, argv, args);
	if (!error.empty())
	{
		std::cerr << (argc > 0 ? argv[0] : "swba") << ": error: " << error << " (see --help)\n";
		return 2;
	}
	std::vector<const char*> ptrs;
	for (const auto& a : args) ptrs.push_back(a.c_str());
	OneLineOutput out;
	out.extra_argument_hint = extra_argument_hint;
	// MRPT's bundled TCLAP forgets, without deleting it, the output object its CmdLine allocated when
	// another one is set (16 bytes per command line, LeakSanitizer's only report): free it here.
	const std::unique_ptr<TCLAP::CmdLineOutput> tclap_default_output(cmd.getOutput());
	cmd.setOutput(&out);
	const bool ok = cmd.parse(static_cast<int>(ptrs.size()), ptrs.data());
	cmd.setOutput(nullptr);
	if (ok) return std::nullopt;
	return out.failed ? 2 : 0;
}
}  // namespace swba::app

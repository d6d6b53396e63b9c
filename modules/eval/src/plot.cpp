// Headless gnuplot plots (data file + script, rendered to PNG and SVG when gnuplot exists).
#include "swba/eval/plot.h"
#include "swba/eval/text_format.h"
#include <swba/core/file.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace swba::eval
{
namespace fs = std::filesystem;

std::string find_gnuplot(const PlotOptions& options)
{
	const std::string& exe = options.gnuplot;
	if (exe.empty()) return {};
	if (exe.find('/') != std::string::npos) return ::access(exe.c_str(), X_OK) == 0 ? exe : std::string();
	const char* path_env = std::getenv("PATH");
	if (!path_env) return {};
	std::istringstream ss(path_env);
	std::string dir;
	while (std::getline(ss, dir, ':'))
	{
		if (dir.empty()) continue;
		const std::string candidate = (fs::path(dir) / exe).string();
		if (::access(candidate.c_str(), X_OK) == 0 && !fs::is_directory(candidate)) return candidate;
	}
	return {};
}

namespace
{
/** A gnuplot string literal in double quotes (backslash and quote escaped). */
std::string gp_string(const std::string& s)
{
	std::string out = "\"";
	for (char c : s)
	{
		if (c == '"' || c == '\\') out += '\\';
		out += (c == '\n') ? ' ' : c;
	}
	return out + "\"";
}

/** A single-quoted shell word. */
std::string shell_quote(const std::string& s)
{
	std::string out = "'";
	for (char c : s) out += (c == '\'') ? std::string("'\\''") : std::string(1, c);
	return out + "'";
}


}  // namespace

namespace
{
/** min … max of the x values of the series that set the axes (the extent of a band). */
std::optional<AxisRange> band_extent(const LinePlot& plot)
{
	if (plot.xrange) return plot.xrange;
	std::vector<double> xs;
	for (const auto& s : plot.series)
		if (!s.clipped) xs.insert(xs.end(), s.x.begin(), s.x.end());
	return data_range(xs, 0.0);
}

/** One block per series (x y [colour]), then one per band (x low high at both ends of the data),
 * separated by two blank lines (gnuplot's `index`). */
void write_plot_data(const std::string& dat_path, const LinePlot& plot)
{
	const auto num = [](double v) { return format_significant(v, 10); };
	write_file_atomically(dat_path, [&](std::ostream& f) {
		for (const auto& s : plot.series)
		{
			f << "# " << s.label << (s.clipped ? " (clipped)" : "") << "\n";
			for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); i++)
			{
				f << num(s.x[i]) << ' ' << num(s.y[i]);
				if (!s.color.empty()) f << ' ' << (i < s.color.size() ? num(s.color[i]) : "nan");
				f << '\n';
			}
			if (s.x.empty()) f << "nan nan\n";	 // keeps the block (and its index) present
			f << "\n\n";
		}
		const auto extent = band_extent(plot);
		for (const auto& b : plot.bands)
		{
			f << "# " << b.label << "\n";
			if (extent)
				for (double x : {extent->min, extent->max}) f << num(x) << ' ' << num(b.low) << ' ' << num(b.high) << '\n';
			else
				f << "nan nan nan\n";
			f << "\n\n";
		}
	});
}

/** The gnuplot `plot` command: the bands (under everything), each series, then the reference lines. */
std::string plot_command(const std::string& dat_name, const LinePlot& plot)
{
	std::ostringstream cmd;
	cmd << "plot ";
	bool first = true;
	auto next = [&]() -> std::ostream& {
		cmd << (first ? "" : ", \\\n     ");
		first = false;
		return cmd;
	};
	for (std::size_t j = 0; j < plot.bands.size(); j++)
		next() << gp_string(dat_name) << " index " << plot.series.size() + j
			   << " using 1:2:3 with filledcurves fc rgb \"#d8d8d8\" fs solid 1.0 noborder title "
			   << gp_string(plot.bands[j].label);
	for (std::size_t k = 0; k < plot.series.size(); k++)
	{
		const auto& s = plot.series[k];
		// gnuplot's line types repeat their colours after eight: later series are dashed as well.
		const std::string dashed = k >= 8 ? " dt " + std::to_string(1 + k / 8) : "";
		const std::string style = !s.line_style.empty() ? s.line_style
								  : s.color.empty()		? "lw 2 lt " + std::to_string(k + 1) + dashed
														: std::string("lw 2 lc palette");
		next() << gp_string(dat_name) << " index " << k << " using 1:2" << (s.color.empty() ? "" : ":3") << " with "
			   << (plot.with_points ? "linespoints pt 7 ps 0.5 " : "lines ") << style << " title " << gp_string(s.label);
	}
	for (std::size_t j = 0; j < plot.references.size(); j++)
	{
		const auto& ref = plot.references[j];
		next() << format_significant(ref.value, 10) << " with lines dt 2 lw 2 lt "
			   << plot.series.size() + j + 1 << " title "
			   << gp_string(ref.label + " (" + format_significant(ref.value, 6) + ")");
	}
	if (first) cmd << "NaN notitle";
	cmd << "\n";
	return cmd.str();
}

/** The settings before the plot command: labels, key outside the data, ranges, colour bar. */
void write_plot_settings(std::ostream& f, const LinePlot& plot)
{
	f << "set title " << gp_string(plot.title) << " noenhanced\n";
	// The notes under the x label, left-aligned from the canvas edge (long lines stay readable).
	if (!plot.notes.empty()) f << "set bmargin " << plot.notes.size() + 4 << "\n";
	for (std::size_t i = 0; i < plot.notes.size(); i++)
		f << "set label " << i + 1 << " " << gp_string(plot.notes[i]) << " at character 1, character "
		  << plot.notes.size() - i << " left noenhanced\n";
	f << "set xlabel " << gp_string(plot.xlabel) << " noenhanced\n";
	f << "set ylabel " << gp_string(plot.ylabel) << " noenhanced\n";
	f << "set grid\n";
	bool coloured = false;
	for (const auto& s : plot.series) coloured = coloured || !s.color.empty();
	// Outside the plotting area so that it never hides data; above it when the colour bar takes the right.
	f << (coloured ? "set key outside top center horizontal" : "set key outside right top vertical Left reverse")
	  << " box opaque noenhanced\n";
	if (plot.equal_axes)
		f << "set size ratio -1\n";
	else
		f << "set offsets 0, 0, graph 0.05, graph 0.05\n";  // keep reference lines off the frame
	const auto [xr, yr] = plot_ranges(plot);
	const auto range = [](const AxisRange& r) {
		return "[" + format_significant(r.min, 10) + ":" + format_significant(r.max, 10) + "]";
	};
	if (xr) f << "set xrange " << range(*xr) << "\n";
	if (yr) f << "set yrange " << range(*yr) << "\n";
	if (coloured)
	{
		f << "set palette defined (0 \"#0000c0\", 1 \"#00a0ff\", 2 \"#40c040\", 3 \"#ffc000\", 4 \"#e00000\")\n";
		f << "set cblabel " << gp_string(plot.color_label) << " noenhanced\n";
		if (plot.color_range) f << "set cbrange " << range(*plot.color_range) << "\n";
	}
}

/** The script, run from inside the plot directory so that it refers to files by name only. */
void write_plot_script(const std::string& gp_path, const std::string& basename, const LinePlot& plot,
					   const PlotOptions& options)
{
	const std::string gp_name = basename + ".gp";
	write_file_atomically(gp_path, [&](std::ostream& f) {
		f << "# generated by swba (swba::eval::plot_lines); run: cd <this dir> && gnuplot " << gp_name << "\n";
		write_plot_settings(f, plot);
		const std::string cmd = plot_command(basename + ".dat", plot);
		const std::string size = std::to_string(options.width_px) + "," + std::to_string(options.height_px);
		if (options.png)
			f << "if (strstrt(GPVAL_TERMINALS, \"pngcairo\") > 0) {\n  set terminal pngcairo size " << size
			  << " font \"sans,10\"\n} else {\n  set terminal png size " << size << "\n}\nset output "
			  << gp_string(basename + ".png") << "\n"
			  << cmd;
		if (options.svg)
			f << "set terminal svg size " << size << " font \"sans,10\"\nset output " << gp_string(basename + ".svg")
			  << "\n"
			  << cmd;
		f << "set output\n";
	});
}

/** Runs gnuplot on the script; adds the images to `out` or a note saying why there are none. */
void render_plot(const std::string& dir, const std::string& basename, const PlotOptions& options, PlotOutput& out)
{
	const std::string gp_name = basename + ".gp";
	const std::string gp_path = (fs::path(dir) / gp_name).string();
	const std::string gnuplot = find_gnuplot(options);
	if (gnuplot.empty())
	{
		out.note = "note: gnuplot not found (" + options.gnuplot + "): plot " + basename +
				   " not rendered; data and script are in " + dir;
		return;
	}
	const std::string log_name = basename + ".gnuplot.log";
	const std::string cmd = "cd " + shell_quote(dir) + " && " + shell_quote(gnuplot) + " " +
							shell_quote(gp_name) + " >/dev/null 2>" + shell_quote(log_name);
	const int rc = std::system(cmd.c_str());
	const std::string log_path = (fs::path(dir) / log_name).string();
	if (rc != 0)
	{
		out.note = "note: gnuplot failed on " + gp_path + " (see " + log_path + ")";
		return;
	}
	std::error_code rm_ec;
	if (fs::exists(log_path) && fs::file_size(log_path, rm_ec) == 0) fs::remove(log_path, rm_ec);
	bool all = true;
	for (const char* ext : {".png", ".svg"})
	{
		if ((ext[1] == 'p' && !options.png) || (ext[1] == 's' && !options.svg)) continue;
		const std::string img = (fs::path(dir) / (basename + ext)).string();
		if (fs::exists(img))
			out.files.push_back(img);
		else
			all = false;
	}
	out.rendered = all;
	if (!all) out.note = "note: gnuplot did not produce every image for " + gp_path;
}
}  // namespace

PlotOutput plot_lines(const std::string& dir, const std::string& basename, const LinePlot& plot,
					  const PlotOptions& options)
{
	PlotOutput out;
	std::error_code ec;
	fs::create_directories(dir, ec);
	if (!fs::is_directory(dir)) throw std::runtime_error("cannot create plot directory '" + dir + "'");
	const std::string dat_path = (fs::path(dir) / (basename + ".dat")).string();
	const std::string gp_path = (fs::path(dir) / (basename + ".gp")).string();
	write_plot_data(dat_path, plot);
	out.files.push_back(dat_path);
	write_plot_script(gp_path, basename, plot, options);
	out.files.push_back(gp_path);
	render_plot(dir, basename, options, out);
	return out;
}

std::optional<AxisRange> data_range(const std::vector<double>& values, double margin)
{
	std::optional<AxisRange> r;
	for (double v : values)
	{
		if (!std::isfinite(v)) continue;
		if (!r)
			r = AxisRange{v, v};
		else
			r = AxisRange{std::min(r->min, v), std::max(r->max, v)};
	}
	if (!r) return r;
	const double pad = (r->max > r->min ? r->max - r->min : std::max(std::abs(r->min), 1.0)) * margin;
	return AxisRange{r->min - pad, r->max + pad};
}

std::pair<std::optional<AxisRange>, std::optional<AxisRange>> plot_ranges(const LinePlot& plot)
{
	bool any_clipped = false;
	for (const auto& s : plot.series) any_clipped = any_clipped || s.clipped;
	for (const auto& r : plot.references) any_clipped = any_clipped || r.clipped;
	std::pair<std::optional<AxisRange>, std::optional<AxisRange>> out{plot.xrange, plot.yrange};
	if (!any_clipped) return out;
	std::vector<double> xs, ys;
	for (const auto& s : plot.series)
		if (!s.clipped)
		{
			xs.insert(xs.end(), s.x.begin(), s.x.end());
			ys.insert(ys.end(), s.y.begin(), s.y.end());
		}
	for (const auto& r : plot.references)
		if (!r.clipped) ys.push_back(r.value);
	for (const auto& b : plot.bands) ys.insert(ys.end(), {b.low, b.high});
	if (!out.first) out.first = data_range(xs);
	if (!out.second) out.second = data_range(ys);
	return out;
}
}  // namespace swba::eval

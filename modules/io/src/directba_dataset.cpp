#include <swba/io/directba_dataset.h>

#include <swba/core/file.h>
#include <swba/core/memory_budget.h>
#include <swba/io/rawlog.h>

#include <mrpt/img/CImage.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <new>
#include <sstream>
#include <stdexcept>
#include <sys/stat.h>

namespace swba::io
{
namespace
{
bool file_exists(const std::string& path)
{
	struct stat st
	{
	};
	return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

/** Splits a line into numbers; throws with file:line if a token is not a finite number or the
 * count differs from `expected`. Returns false for blank and '#' lines. */
bool parse_numbers(const std::string& path, int line_no, const std::string& line, size_t expected,
				   const char* what, std::vector<double>& out)
{
	out.clear();
	std::istringstream ss(line);
	std::string tok;
	bool first = true;
	while (ss >> tok)
	{
		if (first && tok[0] == '#') return false;
		first = false;
		errno = 0;
		char* end = nullptr;
		const double d = std::strtod(tok.c_str(), &end);
		if (end == tok.c_str() || *end != '\0' || errno == ERANGE || !std::isfinite(d))
			throw std::runtime_error(path + ":" + std::to_string(line_no) + ": '" + tok + "' is not a finite number");
		out.push_back(d);
	}
	if (out.empty()) return false;
	if (out.size() != expected)
		throw std::runtime_error(path + ":" + std::to_string(line_no) + ": expected " + std::to_string(expected) +
								 " columns (" + what + "), found " + std::to_string(out.size()));
	return true;
}

std::ifstream open_or_throw(const std::string& path)
{
	if (!file_exists(path)) throw std::runtime_error(path + ": file not found");
	return open_input_file(path);
}
std::uint64_t file_size_or_zero(const std::string& path)
{
	std::error_code ec;
	const auto n = std::filesystem::file_size(path, ec);
	return ec ? 0 : static_cast<std::uint64_t>(n);
}

/** Checks a PNG before any decoder sees it: its declared pixels must fit the budget (8 bytes per pixel
 * covers the decoded image at up to 16 bits × 4 channels, or the float intensity image), read from the
 * IHDR chunk before a decoder allocates the declared size; and its chunks must run whole to IEND, so that
 * a truncated file is reported here, by name and offset, instead of by the decoder's own message on
 * stderr (`size`: the file's, in bytes). Not a PNG, or too short to tell: left to the decoder. */
void check_png(const std::string& path, std::uint64_t size, std::uint64_t budget)
{
	std::ifstream f(path, std::ios::binary);
	unsigned char h[24] = {};
	if (!f.read(reinterpret_cast<char*>(h), sizeof h)) return;
	static const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
	if (!std::equal(sig, sig + 8, h) || std::string(reinterpret_cast<const char*>(h + 12), 4) != "IHDR") return;
	auto be32 = [](const unsigned char* b) {
		return (std::uint64_t(b[0]) << 24) | (std::uint64_t(b[1]) << 16) | (std::uint64_t(b[2]) << 8) | std::uint64_t(b[3]);
	};
	const std::uint64_t w = be32(h + 16), ht = be32(h + 20);
	if (w * ht * 8 > budget)
		throw std::runtime_error(path + ": declares " + std::to_string(w) + "x" + std::to_string(ht) +
								 " pixels, more than the image memory budget of " + std::to_string(budget >> 20) +
								 " MiB allows (corrupt, or a decompression bomb)");
	std::uint64_t at = 8;  // each chunk: length (4), type (4), data (length), CRC (4)
	unsigned char c[8];
	while (f.seekg(static_cast<std::streamoff>(at)) && f.read(reinterpret_cast<char*>(c), sizeof c))
	{
		const std::string type(reinterpret_cast<const char*>(c + 4), 4);
		const std::uint64_t end = at + 12 + be32(c);
		if (end > size)
			throw std::runtime_error(path + ": truncated PNG: its " + type + " chunk at byte " + std::to_string(at) +
									 " ends at byte " + std::to_string(end) + ", the file at " + std::to_string(size));
		if (type == "IEND") return;
		at = end;
	}
	throw std::runtime_error(path + ": truncated PNG: no IEND chunk (the file ends at byte " + std::to_string(size) + ")");
}
}  // namespace

std::uint64_t image_memory_budget(std::uint64_t file_bytes) { return scaled_memory_budget(file_bytes, 64); }

PinholeIntrinsics directba_dataset_intrinsics() { return {277.34, 291.402, 312.234, 239.777}; }

IntensityImage load_intensity_image(const std::string& path)
{
	if (!file_exists(path)) throw std::runtime_error(path + ": image file not found");
	const std::uint64_t size = file_size_or_zero(path), budget = image_memory_budget(size);
	if (size == 0) throw std::runtime_error(path + ": cannot decode image (empty file)");
	check_png(path, size, budget);
	mrpt::img::CImage img;
	bool ok = false;
	try
	{
		const ScopedMemoryBudget guard(budget);  // other formats, and decoders' own buffers
		ok = img.loadFromFile(path);
	}
	catch (const std::bad_alloc&)
	{
		throw std::runtime_error(path + ": decoding needs more than the image memory budget of " +
								 std::to_string(budget >> 20) + " MiB (corrupt, or a decompression bomb)");
	}
	catch (const std::exception& e)
	{
		// The decoder's reason in one line (an MRPT exception spans lines: banner, message, call stack).
		throw std::runtime_error(path + ": cannot decode image (" + mrpt_exception_summary(e.what(), true) + ")");
	}
	if (!ok || img.getWidth() == 0 || img.getHeight() == 0)
		throw std::runtime_error(path + ": cannot decode image");
	if (img.isColor()) img = img.grayscale();
	if (img.getPixelDepth() != mrpt::img::PixelDepth::D8U)
		throw std::runtime_error(path + ": only 8-bit images are supported");
	IntensityImage out(static_cast<int>(img.getWidth()), static_cast<int>(img.getHeight()));
	for (int r = 0; r < out.height; r++)
	{
		const uint8_t* line = img.ptrLine<uint8_t>(static_cast<unsigned>(r));
		for (int c = 0; c < out.width; c++) out.at(c, r) = static_cast<float>(line[c]);
	}
	return out;
}

void read_directba_poses(const std::string& path, std::vector<double>& timestamps,
						 std::vector<mrpt::poses::CPose3D>& world_from_camera)
{
	timestamps.clear();
	world_from_camera.clear();
	auto f = open_or_throw(path);
	std::string line;
	std::vector<double> v;
	for (int line_no = 1; std::getline(f, line); line_no++)
	{
		if (!parse_numbers(path, line_no, line, 8, "t tx ty tz qx qy qz qw", v)) continue;
		const Eigen::Quaterniond q_raw(v[7], v[4], v[5], v[6]);
		if (q_raw.norm() < 1e-9)
			throw std::runtime_error(path + ":" + std::to_string(line_no) + ": zero quaternion");
		const Eigen::Matrix3d R_cw = q_raw.normalized().toRotationMatrix();
		const Eigen::Vector3d t_cw(v[1], v[2], v[3]);
		mrpt::math::CMatrixDouble33 R;
		R.asEigen() = R_cw.transpose();
		const Eigen::Vector3d t_wc = -R_cw.transpose() * t_cw;
		timestamps.push_back(v[0]);
		world_from_camera.emplace_back(R, mrpt::math::CVectorFixedDouble<3>({t_wc.x(), t_wc.y(), t_wc.z()}));
	}
	if (world_from_camera.empty()) throw std::runtime_error(path + ": no poses");
}

std::vector<DirectBAPoint> read_directba_points(const std::string& path)
{
	auto f = open_or_throw(path);
	std::vector<DirectBAPoint> points;
	std::string line;
	std::vector<double> v;
	for (int line_no = 1; std::getline(f, line); line_no++)
	{
		if (!parse_numbers(path, line_no, line, 3 + kDirectBAPatchSize, "x y z + 16 patch values", v)) continue;
		DirectBAPoint p;
		p.position = Eigen::Vector3d(v[0], v[1], v[2]);
		for (int k = 0; k < kDirectBAPatchSize; k++) p.patch[k] = v[3 + k];
		points.push_back(p);
	}
	if (points.empty()) throw std::runtime_error(path + ": no points");
	return points;
}

DirectBADataset read_directba_dataset(const std::string& dir, const PinholeIntrinsics& intrinsics)
{
	DirectBADataset ds;
	ds.intrinsics = intrinsics;
	const std::string base = dir.empty() ? std::string(".") : dir;
	std::error_code ec;
	if (!std::filesystem::exists(base, ec)) throw std::runtime_error(base + ": directory does not exist");
	if (!std::filesystem::is_directory(base, ec))
		throw std::runtime_error(base + ": is not a directory (a data set is a directory of poses.txt, points.txt and PNGs)");
	read_directba_poses(base + "/poses.txt", ds.timestamps, ds.world_from_camera);
	ds.points = read_directba_points(base + "/points.txt");
	for (size_t i = 0; i < ds.world_from_camera.size(); i++)
	{
		auto img = std::make_shared<IntensityImage>(load_intensity_image(base + "/" + std::to_string(i) + ".png"));
		if (!ds.images.empty() && (img->width != ds.images[0]->width || img->height != ds.images[0]->height))
			throw std::runtime_error(base + "/" + std::to_string(i) + ".png: size " + std::to_string(img->width) + "x" +
									 std::to_string(img->height) + " differs from image 0");
		ds.images.push_back(std::move(img));
	}
	return ds;
}

}  // namespace swba::io

// Reader of the shipped direct-BA data set (share/data/directba): contents, pose convention, and clear errors on
// missing/unreadable images and malformed text files.
#include <swba/core/manifold.h>
#include <swba/factors/photometric_patch.h>
#include <swba/io/directba_dataset.h>

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <unistd.h>

using namespace swba;
namespace fs = std::filesystem;

namespace
{
const std::string kDir = std::string(SWBA_DATA_DIR) + "/directba";

/** Runs `f`, expects std::runtime_error whose message contains every `parts` string. */
void expect_error(const std::function<void()>& f, std::initializer_list<std::string> parts)
{
	try
	{
		f();
		ADD_FAILURE() << "no exception thrown";
	}
	catch (const std::runtime_error& e)
	{
		const std::string what = e.what();
		for (const auto& p : parts) EXPECT_NE(what.find(p), std::string::npos) << "'" << p << "' not in: " << what;
	}
}

/** A fresh temporary copy of the shipped data set (or parts of it). */
struct TempDataset
{
	fs::path dir;
	explicit TempDataset(const std::string& name)
	{
		dir = fs::temp_directory_path() / ("swba_directba_" + name + "_" + std::to_string(::getpid()));
		fs::remove_all(dir);
		fs::create_directories(dir);
		for (const char* f : {"poses.txt", "points.txt", "0.png", "1.png", "2.png", "3.png", "4.png", "5.png", "6.png"})
			fs::copy_file(fs::path(kDir) / f, dir / f);
	}
	~TempDataset() { fs::remove_all(dir); }
	std::string path(const std::string& f) const { return (dir / f).string(); }
	void write(const std::string& f, const std::string& content) const
	{
		std::ofstream o(path(f), std::ios::trunc);
		o << content;
	}
};
}  // namespace

TEST(DirectBAIO, ReadsTheShippedDataSet)
{
	const auto ds = io::read_directba_dataset(kDir);
	ASSERT_EQ(ds.world_from_camera.size(), 7u);
	ASSERT_EQ(ds.images.size(), 7u);
	ASSERT_EQ(ds.points.size(), 4118u);
	for (const auto& img : ds.images)
	{
		EXPECT_EQ(img->width, 640);
		EXPECT_EQ(img->height, 480);
		const auto mm = std::minmax_element(img->pixels.begin(), img->pixels.end());
		EXPECT_GE(*mm.first, 0.f);
		EXPECT_LE(*mm.second, 255.f);
		EXPECT_GT(*mm.second - *mm.first, 100.f);  // real content, not a blank image
	}
	// First line of points.txt.
	EXPECT_DOUBLE_EQ(ds.points[0].position.x(), -0.471274);
	EXPECT_DOUBLE_EQ(ds.points[0].position.z(), 3.76621);
	EXPECT_DOUBLE_EQ(ds.points[0].patch[0], 140.453);
	EXPECT_DOUBLE_EQ(ds.points[0].patch[15], 337.327);
	// First line of poses.txt is camera-from-world: the reader returns its inverse.
	const Eigen::Quaterniond q_cw(0.978416, -0.0651624, 0.112345, -0.160729);
	const Eigen::Vector3d t_cw(0.702775, 0.084358, 0.00503326);
	const Eigen::Vector3d c = -(q_cw.normalized().toRotationMatrix().transpose() * t_cw);
	EXPECT_NEAR(ds.world_from_camera[0].x(), c.x(), 1e-12);
	EXPECT_NEAR(ds.world_from_camera[0].y(), c.y(), 1e-12);
	EXPECT_NEAR(ds.world_from_camera[0].z(), c.z(), 1e-12);
	EXPECT_NEAR(ds.timestamps[0], 1.46323e9, 1.0);
	EXPECT_EQ(ds.intrinsics.fx, 277.34);
}

TEST(DirectBAIO, PosesAreCameraFromWorldInTheFile)
{
	// Check by projecting: with T_wc = T_cw⁻¹ (the reader's reading) the patches match the images
	// far better than with the file's pose taken as world-from-camera.
	const auto ds = io::read_directba_dataset(kDir);
	auto median_residual = [&](bool invert) {
		std::vector<double> res;
		for (size_t j = 0; j < ds.images.size(); j++)
		{
			double x[12];
			SE3Manifold::from_pose(invert ? -ds.world_from_camera[j] : ds.world_from_camera[j], x);
			for (const auto& p : ds.points)
			{
				const PhotometricPatchFactor f(p.patch, ds.images[j], ds.intrinsics);
				const double* xs[2] = {x, p.position.data()};
				double r[16];
				if (!f.evaluate(xs, r, nullptr)) continue;
				for (double e : r) res.push_back(std::abs(e));
			}
		}
		EXPECT_GT(res.size(), 10000u);
		std::nth_element(res.begin(), res.begin() + res.size() / 2, res.end());
		return res[res.size() / 2];
	};
	const double good = median_residual(false), swapped = median_residual(true);
	EXPECT_LT(good, 15.0);
	EXPECT_GT(swapped, 3 * good);
}

TEST(DirectBAIO, MissingFilesGiveErrorsNamingThem)
{
	expect_error([] { io::read_directba_dataset("/nonexistent/swba/dir"); }, {"/nonexistent/swba/dir", "does not exist"});
	TempDataset t("missing");
	fs::remove(t.dir / "6.png");
	expect_error([&] { io::read_directba_dataset(t.dir.string()); }, {"6.png", "not found"});
	fs::remove(t.dir / "points.txt");
	expect_error([&] { io::read_directba_dataset(t.dir.string()); }, {"points.txt", "not found"});
	expect_error([] { io::load_intensity_image("/nonexistent.png"); }, {"/nonexistent.png"});
}

TEST(DirectBAIO, UnreadableImageGivesAnError)
{
	TempDataset t("unreadable");
	t.write("3.png", "this is not a PNG file\n");
	expect_error([&] { io::read_directba_dataset(t.dir.string()); }, {"3.png", "cannot decode"});
	t.write("3.png", "");
	expect_error([&] { io::read_directba_dataset(t.dir.string()); }, {"3.png", "cannot decode image (empty file)"});
	// One line, without the decoder's banner (MRPT's exception for an empty buffer spans several lines).
	try
	{
		io::read_directba_dataset(t.dir.string());
	}
	catch (const std::runtime_error& e)
	{
		const std::string what = e.what();
		EXPECT_EQ(what.find('\n'), std::string::npos) << what;
		EXPECT_EQ(what.find("MRPT exception"), std::string::npos) << what;
	}
}

TEST(DirectBAIO, TruncatedPngIsReportedByOffsetAndTheDecoderPrintsNothing)
{
	TempDataset t("truncated");
	std::ifstream in(t.path("3.png"), std::ios::binary);
	const std::string png((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
	ASSERT_GT(png.size(), 3000u);
	testing::internal::CaptureStderr();
	t.write("3.png", png.substr(0, 3000));  // inside the first IDAT chunk
	expect_error([&] { io::read_directba_dataset(t.dir.string()); }, {"3.png", "truncated PNG", "IDAT", "3000"});
	t.write("3.png", png.substr(0, 33));  // IHDR whole, nothing after it
	expect_error([&] { io::read_directba_dataset(t.dir.string()); }, {"3.png", "truncated PNG", "no IEND"});
	EXPECT_EQ(testing::internal::GetCapturedStderr(), "");  // libpng's own message never comes
	t.write("3.png", png);
	EXPECT_NO_THROW(io::load_intensity_image(t.path("3.png")));
}

TEST(DirectBAIO, WrongColumnCountsAndBadTokensGiveLineNumbers)
{
	TempDataset t("columns");
	t.write("points.txt", "1 2 3 " + std::string(16 * 2, ' ') + "\n");  // a line with 3 columns
	expect_error([&] { io::read_directba_points(t.path("points.txt")); }, {"points.txt:1", "expected 19", "found 3"});
	std::string line19 = "0.1 0.2 3";
	for (int k = 0; k < 16; k++) line19 += " 100";
	t.write("points.txt", line19 + "\n" + line19 + " 7\n");  // second line has 20 columns
	expect_error([&] { io::read_directba_points(t.path("points.txt")); }, {"points.txt:2", "expected 19", "found 20"});
	t.write("points.txt", "# comment\n\n" + line19 + "\n0.1 0.2 x3" + line19.substr(9) + "\n");
	expect_error([&] { io::read_directba_points(t.path("points.txt")); }, {"points.txt:4", "'x3'"});
	t.write("points.txt", line19 + "\n");
	EXPECT_EQ(io::read_directba_points(t.path("points.txt")).size(), 1u);

	t.write("poses.txt", "1 0 0 0 0 0 0 1\n2 0 0 0 0 0 1\n");  // 7 columns on line 2
	std::vector<double> ts;
	std::vector<mrpt::poses::CPose3D> poses;
	expect_error([&] { io::read_directba_poses(t.path("poses.txt"), ts, poses); },
				 {"poses.txt:2", "expected 8", "found 7"});
	t.write("poses.txt", "1 0 0 0 0 0 0 0\n");
	expect_error([&] { io::read_directba_poses(t.path("poses.txt"), ts, poses); }, {"poses.txt:1", "zero quaternion"});
	t.write("poses.txt", "1 0 0 0 0 0 0 nan\n");
	expect_error([&] { io::read_directba_poses(t.path("poses.txt"), ts, poses); }, {"poses.txt:1", "not a finite"});
	t.write("poses.txt", "\n");
	expect_error([&] { io::read_directba_poses(t.path("poses.txt"), ts, poses); }, {"no poses"});
	// The whole data set reader propagates these errors.
	t.write("poses.txt", "1 0 0 0 0 0 0 1 9\n");
	expect_error([&] { io::read_directba_dataset(t.dir.string()); }, {"poses.txt:1", "expected 8"});
}

TEST(DirectBAIO, APngDeclaringGigabytesIsRefusedBeforeDecoding)
{
	// Signature and an IHDR chunk declaring 20000 × 20000 8-bit gray pixels (a few hundred kilobytes
	// of deflated zeros can carry them): refused from the header, whatever follows.
	const fs::path png = fs::temp_directory_path() / ("swba_png_bomb_" + std::to_string(getpid()) + ".png");
	{
		std::ofstream f(png, std::ios::binary);
		const unsigned char bytes[] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n', 0, 0, 0, 13, 'I', 'H', 'D', 'R',
									   0, 0, 0x4e, 0x20, 0, 0, 0x4e, 0x20, 8, 0, 0, 0, 0, 0, 0, 0, 0};
		f.write(reinterpret_cast<const char*>(bytes), sizeof bytes);
	}
	try
	{
		swba::io::load_intensity_image(png.string());
		ADD_FAILURE() << "decoded";
	}
	catch (const std::runtime_error& e)
	{
		EXPECT_NE(std::string(e.what()).find("declares 20000x20000 pixels, more than the image memory budget of 256 MiB"),
				  std::string::npos)
			<< e.what();
	}
	fs::remove(png);
	EXPECT_EQ(swba::io::image_memory_budget(1000), (std::uint64_t(256) << 20) + 64000);
}

// Time-stamp association with evo's rule: nearest stamp, first on ties, |dt| <= t_max_diff, offset.
#include <gtest/gtest.h>
#include <swba/eval/association.h>

#include <random>

using namespace swba::eval;

namespace
{
/** A trajectory whose pose i sits at x = `tag` + i (to tell which pose was matched). */
Trajectory make(const std::vector<double>& stamps, double tag = 0)
{
	Trajectory t;
	for (std::size_t i = 0; i < stamps.size(); i++)
		t.push_back(stamps[i], mrpt::poses::CPose3D(tag + static_cast<double>(i), 0, 0, 0, 0, 0));
	return t;
}

/** The argmin-based reference rule, written as evo does it (linear scan), for cross-checking. */
Association brute_force(const Trajectory& ref, const Trajectory& est, const AssociationOptions& o)
{
	Association a;
	const bool est_longer = est.size() > ref.size();
	const auto& lng = est_longer ? est.stamps : ref.stamps;
	const auto& sht = est_longer ? ref.stamps : est.stamps;
	const double off = est_longer ? o.t_offset : -o.t_offset;
	for (std::size_t i = 0; i < sht.size(); i++)
	{
		std::size_t best = 0;
		double dbest = std::abs((lng[0] + off) - sht[i]);
		for (std::size_t j = 1; j < lng.size(); j++)
		{
			const double d = std::abs((lng[j] + off) - sht[i]);
			if (d < dbest)
			{
				dbest = d;
				best = j;
			}
		}
		if (dbest <= o.t_max_diff)
		{
			(est_longer ? a.ref_ids : a.est_ids).push_back(i);
			(est_longer ? a.est_ids : a.ref_ids).push_back(best);
		}
	}
	return a;
}
}  // namespace

TEST(Association, IdenticalStampsPairOneToOne)
{
	const Trajectory ref = make({0, 1, 2, 3}), est = make({0, 1, 2, 3});
	const Association a = associate(ref, est);
	EXPECT_EQ(a.ref_ids, (std::vector<std::size_t>{0, 1, 2, 3}));
	EXPECT_EQ(a.est_ids, (std::vector<std::size_t>{0, 1, 2, 3}));
}

TEST(Association, JitterWithinToleranceIsMatchedBeyondIsDropped)
{
	const Trajectory ref = make({0, 1, 2, 3, 4});
	const Trajectory est = make({0.004, 0.995, 2.0101, 3.0099, 4.02});
	const Association a = associate(ref, est);  // t_max_diff = 0.01
	EXPECT_EQ(a.est_ids, (std::vector<std::size_t>{0, 1, 3}));
	EXPECT_EQ(a.ref_ids, (std::vector<std::size_t>{0, 1, 3}));
	AssociationOptions wide;
	wide.t_max_diff = 0.05;
	EXPECT_EQ(associate(ref, est, wide).size(), 5u);
}

TEST(Association, DroppedPosesInTheEstimate)
{
	const Trajectory ref = make({0, 1, 2, 3, 4, 5, 6});
	const Trajectory est = make({1, 2, 5, 6});  // 0, 3, 4 dropped
	const Association a = associate(ref, est);
	EXPECT_EQ(a.ref_ids, (std::vector<std::size_t>{1, 2, 5, 6}));
	EXPECT_EQ(a.est_ids, (std::vector<std::size_t>{0, 1, 2, 3}));
	// The other way round (estimate longer than reference) too.
	const Association b = associate(est, ref);
	EXPECT_EQ(b.ref_ids, (std::vector<std::size_t>{0, 1, 2, 3}));
	EXPECT_EQ(b.est_ids, (std::vector<std::size_t>{1, 2, 5, 6}));
}

TEST(Association, DuplicateStampsFirstWinsAndShortSideMayRepeat)
{
	// Duplicates in the longer trajectory: the first of the equal stamps is taken (argmin).
	const Trajectory ref = make({0, 1, 1, 1, 2, 3});
	const Trajectory est = make({1, 2});
	const Association a = associate(ref, est);
	EXPECT_EQ(a.ref_ids, (std::vector<std::size_t>{1, 4}));
	// Duplicates in the shorter trajectory: both pair with the same pose of the longer one.
	const Trajectory ref2 = make({0, 1, 2, 3, 4});
	const Trajectory est2 = make({1, 1, 3});
	const Association b = associate(ref2, est2);
	EXPECT_EQ(b.est_ids, (std::vector<std::size_t>{0, 1, 2}));
	EXPECT_EQ(b.ref_ids, (std::vector<std::size_t>{1, 1, 3}));
}

TEST(Association, TieBetweenTwoStampsTakesTheEarlier)
{
	const Trajectory ref = make({0.0, 0.5, 1.0, 1.5});
	const Trajectory est = make({0.75});
	AssociationOptions o;
	o.t_max_diff = 0.3;
	const Association a = associate(ref, est, o);
	ASSERT_EQ(a.size(), 1u);
	EXPECT_EQ(a.ref_ids[0], 1u);  // 0.5 and 1.0 are both 0.25 away
}

TEST(Association, OffsetIsAddedToTheEstimate)
{
	const Trajectory ref = make({10, 11, 12, 13});
	const Trajectory est = make({0, 1, 2});
	EXPECT_EQ(associate(ref, est).size(), 0u);
	AssociationOptions o;
	o.t_offset = 11.0;	// est stamps + 11 = 11, 12, 13
	const Association a = associate(ref, est, o);
	EXPECT_EQ(a.ref_ids, (std::vector<std::size_t>{1, 2, 3}));
	EXPECT_EQ(a.est_ids, (std::vector<std::size_t>{0, 1, 2}));
	// Same with the estimate as the longer trajectory.
	const Trajectory est_long = make({-1, 0, 1, 2, 3, 4});
	const Association b = associate(ref, est_long, o);
	EXPECT_EQ(b.ref_ids, (std::vector<std::size_t>{0, 1, 2, 3}));
	EXPECT_EQ(b.est_ids, (std::vector<std::size_t>{0, 1, 2, 3}));
}

TEST(Association, MatchesALinearScanOnRandomStamps)
{
	std::mt19937 rng(42);
	std::uniform_real_distribution<double> step(0.0, 0.02), jitter(-0.012, 0.012);
	std::bernoulli_distribution drop(0.2), dup(0.1);
	for (int trial = 0; trial < 50; trial++)
	{
		std::vector<double> r, e;
		double t = 0;
		for (int i = 0; i < 200; i++)
		{
			t += dup(rng) ? 0.0 : step(rng);
			r.push_back(t);
			if (!drop(rng)) e.push_back(t + jitter(rng));
		}
		std::sort(e.begin(), e.end());
		AssociationOptions o;
		o.t_offset = (trial % 3 == 0) ? 0.003 : 0.0;
		const Trajectory ref = make(r), est = make(e);
		for (const auto& [a_ref, a_est] : {std::pair{&ref, &est}, std::pair{&est, &ref}})
		{
			const Association fast = associate(*a_ref, *a_est, o);
			const Association slow = brute_force(*a_ref, *a_est, o);
			ASSERT_EQ(fast.ref_ids, slow.ref_ids) << "trial " << trial;
			ASSERT_EQ(fast.est_ids, slow.est_ids) << "trial " << trial;
		}
	}
}

TEST(Association, NoMatchThrowsFromAssociateTrajectories)
{
	Trajectory r, e;
	EXPECT_THROW(associate_trajectories(make({0, 1}), make({5, 6}), {}, r, e), std::runtime_error);
	EXPECT_EQ(associate(make({}), make({1})).size(), 0u);
	EXPECT_EQ(associate(make({1}), make({})).size(), 0u);
}

TEST(Association, AssociatedTrajectoriesKeepTheirPoses)
{
	Trajectory r, e;
	associate_trajectories(make({0, 1, 2, 3}, 100), make({1.001, 3}, 200), {}, r, e);
	ASSERT_EQ(r.size(), 2u);
	EXPECT_EQ(r.poses[0].x(), 101.0);
	EXPECT_EQ(r.poses[1].x(), 103.0);
	EXPECT_EQ(e.poses[0].x(), 200.0);
	EXPECT_EQ(e.stamps[0], 1.001);
}

/** \file mrpt_adapter.h
 * Feeding the sliding-window estimator from MRPT objects in an online loop: an action collection +
 * sensory frame pair (what CRawlog::readActionObservationPair or a live robot gives), or an
 * odometry increment + a CObservationBearingRange, converted into the io::RawlogStep that
 * SlidingWindowEstimator::process() takes — with the same validation as swba::io::read_rawlog, so that
 * an application fed object by object gets exactly the poses `swba run` gets from the file.
 *
 * \code
 *   swba::estimators::MrptSlidingWindow slam(options);           // SlidingWindowOptions
 *   for (const swba::io::RawlogStep& step : swba::io::read_rawlog(path).steps) {   // or a robot's pairs
 *     slam.process(step.actions, step.observations);   // throws std::invalid_argument on invalid data
 *     mrpt::poses::CPose3D now = slam.current_pose();
 *   }
 *   slam.finish();
 * \endcode
 * (examples/online_slam is a whole application.) */
#pragma once

#include <swba/estimators/sliding_window.h>
#include <swba/io/rawlog.h>

#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>

#include <cstddef>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

namespace swba::estimators
{
/** Options of MrptStepConverter. */
struct MrptStepConverterOptions
{
	/** Readings with landmarkID < 0 are invalid (dropped and counted). Default true. Set it false to give
	 * them to the window's data association (SlidingWindowOptions::association: Auto takes it when a
	 * reading has no ID; doc/association.md), as `swba run` does. Same meaning as
	 * io::RawlogReaderOptions::require_landmark_ids. */
	bool require_landmark_ids = true;
};

/** Converts MRPT objects into io::RawlogStep, numbering the steps 0, 1, 2, … (the step index is the
 * trajectory clock: the estimate after step k has t = k + 1), with io::read_rawlog's own conversion
 * (io::RawlogStepConverter): the sensor description is carried to steps whose frame has no
 * bearing-range observation. */
class MrptStepConverter
{
   public:
	explicit MrptStepConverter(const MrptStepConverterOptions& options = {})
		: converter_(options.require_landmark_ids)
	{
	}

	/** The next step from an action collection (its first robot movement, 2D or 3D, is the odometry;
	 * none → has_odometry = false) and the sensory frame that follows it (its
	 * CObservationBearingRange readings). Invalid single readings (non-finite, range ≤ 0, unknown ID)
	 * are dropped and counted in RawlogStep::skipped_readings; the step's `observations` is then a
	 * cleaned copy. Cost: O(readings) plus a copy of the frame when readings were dropped.
	 * Throws std::invalid_argument (naming the step) on a null pointer, a non-finite odometry mean
	 * or covariance, a negative odometry variance, a non-finite sensor pose or noise, or several
	 * bearing-range observations with different sensor poses/noise in one frame. On a throw the
	 * step counter does not advance. */
	io::RawlogStep convert(const mrpt::obs::CActionCollection::Ptr& actions,
						   const mrpt::obs::CSensoryFrame::Ptr& observations);

	/** The next step from an odometry increment (mean and 6×6 covariance in MRPT's
	 * x y z yaw pitch roll order) and one bearing-range observation. Builds the action collection
	 * (a CActionRobotMovement3D) and the sensory frame and converts them as above. Same throws. */
	io::RawlogStep convert(const mrpt::poses::CPose3DPDFGaussian& odometry,
						   const mrpt::obs::CObservationBearingRange& observation);

	/** Steps converted so far (the index the next step gets). */
	std::size_t steps() const { return converter_.steps(); }

   private:
	io::RawlogStepConverter converter_;  ///< read_rawlog's own conversion
};

/** A SlidingWindowEstimator fed with MRPT objects: MrptStepConverter + estimator in one object,
 * for an online loop. Every accessor forwards to estimator(), which gives the full API. */
class MrptSlidingWindow
{
   public:
	/** Throws std::invalid_argument on invalid options (SlidingWindowOptions::validate()). */
	explicit MrptSlidingWindow(const SlidingWindowOptions& options, const MrptStepConverterOptions& converter = {})
		: converter_(converter), estimator_(options)
	{
	}

	/** Converts the pair (see MrptStepConverter::convert) and processes it: one LM solve over the
	 * window (at most options.solver.max_iterations iterations, each a sparse Schur-complement
	 * solve) and, once the window is full, one dense marginalisation of the oldest pose. Throws
	 * std::invalid_argument on invalid data or a step without odometry after the first. */
	const StepSummary& process(const mrpt::obs::CActionCollection::Ptr& actions,
							   const mrpt::obs::CSensoryFrame::Ptr& observations)
	{
		return estimator_.process(converter_.convert(actions, observations));
	}
	/** As above from an odometry increment and one bearing-range observation. */
	const StepSummary& process(const mrpt::poses::CPose3DPDFGaussian& odometry,
							   const mrpt::obs::CObservationBearingRange& observation)
	{
		return estimator_.process(converter_.convert(odometry, observation));
	}
	/** Moves the poses still in the window to the lagged trajectory; call once at the end. */
	void finish() { estimator_.finish(); }

	/** The newest pose (O(1)). */
	mrpt::poses::CPose3D current_pose() const { return estimator_.current_pose(); }
	/** (time, pose) of the window's poses, oldest first (O(W)). */
	std::vector<std::pair<double, mrpt::poses::CPose3D>> window_poses() const { return estimator_.window_poses(); }
	/** World XYZ of every landmark in the state, by ID (O(landmarks)). */
	std::map<std::int32_t, Eigen::Vector3d> landmarks() const { return estimator_.landmarks(); }
	/** What each process() call did. */
	const std::vector<StepSummary>& step_summaries() const { return estimator_.step_summaries(); }
	/** Every landmark in the state with its world XYZ and marginal 3×3 covariance at the current
	 * estimate (SlidingWindowEstimator::landmark_estimates: one factorisation of the window's system,
	 * so call it when needed, not after every step). Not const: the estimator caches the factorisation. */
	std::map<std::int32_t, LandmarkEstimate> landmark_estimates() { return estimator_.landmark_estimates(); }
	/** The landmark ID each reading of each step was given (data association, or the reading's own ID):
	 * assigned_ids()[k][i] for reading i of step k, in the order of that step's readings (O(readings)). */
	std::vector<std::vector<std::int32_t>> assigned_ids() const { return estimator_.assigned_ids(); }

	const SlidingWindowEstimator& estimator() const { return estimator_; }
	const MrptStepConverter& converter() const { return converter_; }

   private:
	MrptStepConverter converter_;
	SlidingWindowEstimator estimator_;
};
}  // namespace swba::estimators

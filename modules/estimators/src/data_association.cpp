// Nearest neighbour through MRPT's data_association_full_covariance; JCBB written here (JointCompatibility).
#include <swba/estimators/data_association.h>

#include <swba/core/chi2.h>

#include <mrpt/math/CMatrixDynamic.h>
#include <mrpt/slam/data_association.h>

#include <Eigen/Cholesky>

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace swba::estimators
{
namespace
{
/** The joint innovation covariance MRPT tests against: the predictions' covariance plus, on each
 * prediction's diagonal block, the noise of a reading there. MRPT takes one covariance per prediction,
 * not per pair; the readings' noise is nearly the same for readings of one landmark (one range), so
 * the block of the nearest reading's noise is used — the mean over the readings when there is none. */
Eigen::MatrixXd innovation_covariance(const AssociationProblem& p)
{
	const int d = p.dim;
	const int n = static_cast<int>(p.predictions.size());
	Eigen::MatrixXd S = p.prediction_covariance;
	Eigen::MatrixXd mean_R = Eigen::MatrixXd::Zero(d, d);
	for (const auto& R : p.reading_covariances) mean_R += R / static_cast<double>(p.reading_covariances.size());
	for (int j = 0; j < n; j++)
	{
		int nearest = -1;
		double best = 0;
		for (std::size_t i = 0; i < p.readings.size(); i++)
		{
			const double e = (p.readings[i] - p.predictions[j]).squaredNorm();
			if (nearest < 0 || e < best) nearest = static_cast<int>(i), best = e;
		}
		S.block(j * d, j * d, d, d) += nearest < 0 ? mean_R : p.reading_covariances[nearest];
	}
	return S;
}

/** Joint compatibility branch and bound (Neira & Tardós 2001): of the pairings of readings with
 * predictions (each prediction at most once) whose pairs are individually compatible and whose joint
 * innovation passes the χ² test of d·k degrees of freedom for k pairs, the one with the most pairs, and
 * among those the smallest joint squared Mahalanobis distance. Written here rather than through MRPT's
 * data_association_full_covariance: MRPT 2.5's JCBB has no joint test, and its bound, tested before each
 * pairing of a reading, stops at the first compatible prediction of a lone reading — it keeps the
 * lowest-indexed candidate, not the nearest (doc/association.md). */
class JointCompatibility
{
   public:
	JointCompatibility(const AssociationProblem& p, double probability) : p_(p)
	{
		const int m = static_cast<int>(p.readings.size());
		const double gate = chi2_quantile(probability, p.dim);
		candidates_.resize(static_cast<std::size_t>(m));
		for (int i = 0; i < m; i++)
		{
			std::vector<std::pair<double, int>> c;
			for (int j = 0; j < static_cast<int>(p.predictions.size()); j++)
			{
				const double d2 = association_distance(p, i, j);
				if (d2 <= gate) c.push_back({d2, j});
			}
			std::sort(c.begin(), c.end());  // nearest first: good hypotheses early prune the rest
			for (const auto& [d2, j] : c) candidates_[static_cast<std::size_t>(i)].push_back(j);
		}
		// later_[i]: readings after i with a candidate, the most pairings the rest can add.
		later_.assign(static_cast<std::size_t>(m) + 1, 0);
		for (int i = m - 1; i >= 0; i--)
			later_[static_cast<std::size_t>(i)] =
				later_[static_cast<std::size_t>(i) + 1] + (candidates_[static_cast<std::size_t>(i)].empty() ? 0 : 1);
		current_.assign(static_cast<std::size_t>(m), -1);
		best_ = current_;
		for (int k = 0; k <= m; k++) joint_gate_.push_back(k ? chi2_quantile(probability, p.dim * k) : 0.0);
	}

	/** The best pairing; `cut`: the search stopped at kMaxNodes, the best found so far is returned. */
	std::vector<int> solve(bool& cut)
	{
		search(0, 0, 0.0);
		cut = nodes_ > kMaxNodes;
		return best_;
	}

	/** Nodes a search may visit: JCBB is exponential in the readings of a step, and a step of many
	 * readings each compatible with several landmarks would not end. The depth-first search, nearest
	 * candidates first, has a full hypothesis after its first descent. On the logs measured the most
	 * a step took was 229 nodes (doc/association.md). */
	static constexpr std::size_t kMaxNodes = 20000;

   private:
	/** Readings from `i` on, with `pairs` pairings of joint distance `d2` made before. The joint distance
	 * never falls as pairings are added, so a branch that cannot pair more than the best, and is not
	 * nearer, is cut. */
	void search(int i, int pairs, double d2)
	{
		if (++nodes_ > kMaxNodes) return;
		const auto can_beat = [&](int most) { return most > best_pairs_ || (most == best_pairs_ && d2 < best_d2_); };
		if (i == static_cast<int>(p_.readings.size()))
		{
			if (can_beat(pairs)) best_ = current_, best_pairs_ = pairs, best_d2_ = d2;
			return;
		}
		const std::size_t ui = static_cast<std::size_t>(i);
		if (!can_beat(pairs + later_[ui])) return;
		for (int j : candidates_[ui])
		{
			if (std::find(current_.begin(), current_.end(), j) != current_.end()) continue;
			current_[ui] = j;
			const double joint = joint_distance();
			if (joint <= joint_gate_[static_cast<std::size_t>(pairs) + 1]) search(i + 1, pairs + 1, joint);
			current_[ui] = -1;
		}
		search(i + 1, pairs, d2);  // the star node: reading i unpaired
	}

	/** Squared Mahalanobis distance of the current pairing's stacked innovation under the predictions'
	 * joint covariance plus each paired reading's own noise. */
	double joint_distance() const
	{
		const int d = p_.dim;
		std::vector<int> readings;
		for (int i = 0; i < static_cast<int>(current_.size()); i++)
			if (current_[static_cast<std::size_t>(i)] >= 0) readings.push_back(i);
		const int k = static_cast<int>(readings.size());
		Eigen::VectorXd e(k * d);
		Eigen::MatrixXd S(k * d, k * d);
		for (int a = 0; a < k; a++)
		{
			const int ia = readings[static_cast<std::size_t>(a)], ja = current_[static_cast<std::size_t>(ia)];
			e.segment(a * d, d) = p_.readings[static_cast<std::size_t>(ia)] - p_.predictions[static_cast<std::size_t>(ja)];
			for (int b = 0; b < k; b++)
			{
				const int jb = current_[static_cast<std::size_t>(readings[static_cast<std::size_t>(b)])];
				S.block(a * d, b * d, d, d) = p_.prediction_covariance.block(ja * d, jb * d, d, d);
			}
			S.block(a * d, a * d, d, d) += p_.reading_covariances[static_cast<std::size_t>(ia)];
		}
		return e.dot(S.ldlt().solve(e));
	}

	const AssociationProblem& p_;
	std::vector<double> joint_gate_;  ///< by pairs k: the χ² quantile of d·k degrees of freedom
	std::vector<std::vector<int>> candidates_;  ///< per reading, its individually compatible predictions
	std::vector<int> later_;
	std::vector<int> current_, best_;
	std::size_t nodes_ = 0;
	int best_pairs_ = 0;
	double best_d2_ = std::numeric_limits<double>::infinity();
};
}  // namespace

double association_distance(const AssociationProblem& p, int i, int j)
{
	const int d = p.dim;
	const Eigen::MatrixXd S = p.prediction_covariance.block(j * d, j * d, d, d) + p.reading_covariances[i];
	const Eigen::VectorXd e = p.readings[i] - p.predictions[j];
	return e.dot(S.ldlt().solve(e));
}

std::vector<int> associate(const AssociationProblem& p, DataAssociation method, double probability, bool* cut)
{
	if (cut) *cut = false;
	if (method != DataAssociation::NearestNeighbour && method != DataAssociation::Jcbb)
		throw std::invalid_argument("associate: the method must be nn or jcbb");
	const int d = p.dim;
	const int m = static_cast<int>(p.readings.size());
	const int n = static_cast<int>(p.predictions.size());
	std::vector<int> out(m, -1);
	if (m == 0 || n == 0) return out;
	if (method == DataAssociation::Jcbb)
	{
		bool stopped = false;
		std::vector<int> best = JointCompatibility(p, probability).solve(stopped);
		if (cut) *cut = stopped;
		return best;
	}
	mrpt::math::CMatrixDouble Z(m, d), Y(n, d);
	for (int i = 0; i < m; i++)
		for (int c = 0; c < d; c++) Z(i, c) = p.readings[i][c];
	for (int j = 0; j < n; j++)
		for (int c = 0; c < d; c++) Y(j, c) = p.predictions[j][c];
	const Eigen::MatrixXd S = innovation_covariance(p);
	mrpt::math::CMatrixDouble Ycov(n * d, n * d);
	for (int r = 0; r < n * d; r++)
		for (int c = 0; c < n * d; c++) Ycov(r, c) = S(r, c);
	mrpt::slam::TDataAssociationResults res;
	mrpt::slam::data_association_full_covariance(Z, Y, Ycov, res, mrpt::slam::assocNN, mrpt::slam::metricMaha,
												 probability, /*DAT_ASOC_USE_KDTREE=*/false);
	for (const auto& [obs, pred] : res.associations)
		if (obs < out.size()) out[obs] = static_cast<int>(pred);
	return out;
}
}  // namespace swba::estimators

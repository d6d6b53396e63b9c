// Nearest neighbour and JCBB through MRPT's data_association_full_covariance.
#include <swba/estimators/data_association.h>

#include <mrpt/math/CMatrixDynamic.h>
#include <mrpt/slam/data_association.h>

#include <Eigen/Cholesky>

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
}  // namespace

double association_distance(const AssociationProblem& p, int i, int j)
{
	const int d = p.dim;
	const Eigen::MatrixXd S = p.prediction_covariance.block(j * d, j * d, d, d) + p.reading_covariances[i];
	const Eigen::VectorXd e = p.readings[i] - p.predictions[j];
	return e.dot(S.ldlt().solve(e));
}

std::vector<int> associate(const AssociationProblem& p, DataAssociation method, double probability)
{
	if (method != DataAssociation::NearestNeighbour && method != DataAssociation::Jcbb)
		throw std::invalid_argument("associate: the method must be nn or jcbb");
	const int d = p.dim;
	const int m = static_cast<int>(p.readings.size());
	const int n = static_cast<int>(p.predictions.size());
	std::vector<int> out(m, -1);
	if (m == 0 || n == 0) return out;
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
	mrpt::slam::data_association_full_covariance(
		Z, Y, Ycov, res, method == DataAssociation::Jcbb ? mrpt::slam::assocJCBB : mrpt::slam::assocNN,
		mrpt::slam::metricMaha, probability, /*DAT_ASOC_USE_KDTREE=*/false);
	for (const auto& [obs, pred] : res.associations)
		if (obs < out.size()) out[obs] = static_cast<int>(pred);
	return out;
}
}  // namespace swba::estimators

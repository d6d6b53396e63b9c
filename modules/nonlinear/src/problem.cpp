#include <swba/nonlinear/problem.h>

#include <stdexcept>
#include <string>

namespace swba
{
namespace
{
/** The entry of `id` in `map`, else std::out_of_range "Problem: unknown <what> <id>". */
template <class Map, class Id>
auto& find_entry(Map& map, Id id, const char* what)
{
	auto it = map.find(id);
	if (it == map.end()) throw std::out_of_range(std::string("Problem: unknown ") + what + " " + std::to_string(id));
	return it->second;
}
}  // namespace

Problem::Variable& Problem::var(VariableId id) { return find_entry(variables_, id, "variable"); }

const Problem::Variable& Problem::var(VariableId id) const { return find_entry(variables_, id, "variable"); }

const Problem::FactorEntry& Problem::factor(FactorId id) const { return find_entry(factors_, id, "factor"); }

VariableId Problem::add_variable(const double* x0, std::shared_ptr<const Manifold> manifold, Group group)
{
	if (!manifold) throw std::invalid_argument("Problem::add_variable: null manifold");
	const VariableId id = next_variable_++;
	Variable v;
	v.value.assign(x0, x0 + manifold->ambient_size());
	v.manifold = std::move(manifold);
	v.group = group;
	variables_.emplace(id, std::move(v));
	return id;
}

VariableId Problem::add_pose(const mrpt::poses::CPose3D& pose, Group group)
{
	double x[SE3Manifold::kAmbient];
	SE3Manifold::from_pose(pose, x);
	return add_variable(x, SE3Manifold::instance(), group);
}

mrpt::poses::CPose3D Problem::pose(VariableId id) const
{
	const auto& v = var(id);
	if (v.manifold->ambient_size() != SE3Manifold::kAmbient || v.manifold->tangent_size() != 6)
		throw std::invalid_argument("Problem::pose: variable " + std::to_string(id) + " is not SE(3)");
	return SE3Manifold::to_pose(v.value.data());
}

void Problem::set_pose(VariableId id, const mrpt::poses::CPose3D& pose)
{
	auto& v = var(id);
	if (v.manifold->ambient_size() != SE3Manifold::kAmbient)
		throw std::invalid_argument("Problem::set_pose: variable " + std::to_string(id) + " is not SE(3)");
	SE3Manifold::from_pose(pose, v.value.data());
}

void Problem::set_value(VariableId id, const double* x)
{
	auto& v = var(id);
	v.value.assign(x, x + v.manifold->ambient_size());
}

FactorId Problem::add_factor(std::shared_ptr<const Factor> factor, std::vector<VariableId> variables,
							 std::shared_ptr<const LossFunction> loss)
{
	if (!factor) throw std::invalid_argument("Problem::add_factor: null factor");
	if (static_cast<int>(variables.size()) != factor->num_variables())
		throw std::invalid_argument("Problem::add_factor: factor expects " +
									std::to_string(factor->num_variables()) + " variables, got " +
									std::to_string(variables.size()));
	for (size_t i = 0; i < variables.size(); i++)
	{
		const auto& v = var(variables[i]);
		if (v.manifold->tangent_size() != factor->tangent_dims()[i])
			throw std::invalid_argument("Problem::add_factor: variable " + std::to_string(variables[i]) +
										" has tangent size " + std::to_string(v.manifold->tangent_size()) +
										", the factor expects " + std::to_string(factor->tangent_dims()[i]));
		for (size_t j = 0; j < i; j++)
			if (variables[j] == variables[i])
				throw std::invalid_argument("Problem::add_factor: variable " + std::to_string(variables[i]) +
											" appears twice");
	}
	const FactorId id = next_factor_++;
	for (VariableId v : variables) var(v).factors.insert(id);
	factors_.emplace(id, FactorEntry{std::move(factor), std::move(variables), std::move(loss)});
	return id;
}

void Problem::remove_factor(FactorId id)
{
	auto it = factors_.find(id);
	if (it == factors_.end()) throw std::out_of_range("Problem: unknown factor " + std::to_string(id));
	for (VariableId v : it->second.variables) var(v).factors.erase(id);
	factors_.erase(it);
}

void Problem::remove_variable(VariableId id)
{
	const std::set<FactorId> fs = var(id).factors;
	for (FactorId f : fs) remove_factor(f);
	variables_.erase(id);
}

double Problem::cost(int* num_dropped) const
{
	double total = 0;
	int dropped = 0;
	std::vector<const double*> xs;
	Eigen::VectorXd r;
	for (const auto& [fid, fe] : factors_)
	{
		xs.clear();
		for (VariableId v : fe.variables) xs.push_back(var(v).value.data());
		r.resize(fe.factor->residual_dim());
		if (!fe.factor->evaluate_whitened(xs.data(), r.data(), nullptr))
		{
			dropped++;
			continue;
		}
		const double s = r.squaredNorm();
		if (fe.loss)
		{
			double rho[3];
			fe.loss->evaluate(s, rho);
			total += 0.5 * rho[0];
		}
		else
			total += 0.5 * s;
	}
	if (num_dropped) *num_dropped = dropped;
	return total;
}
}  // namespace swba

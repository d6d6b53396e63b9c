// Typed robust-loss options over swba::make_loss (see robust_loss.h).
#include <swba/apps/robust_loss.h>

#include <stdexcept>

namespace swba::apps
{
RobustLoss parse_robust_loss(const std::string& name)
{
	for (const RobustLoss loss : {RobustLoss::None, RobustLoss::Huber, RobustLoss::Cauchy})
		if (name == to_string(loss)) return loss;
	make_loss(name, 1.0);  // throws the core's message for a name it does not know
	return RobustLoss::None;  // the names make_loss takes for no loss ("")
}

std::string to_string(RobustLoss loss)
{
	switch (loss)
	{
		case RobustLoss::None: return "none";
		case RobustLoss::Huber: return "huber";
		case RobustLoss::Cauchy: return "cauchy";
	}
	return "?";
}

std::shared_ptr<const LossFunction> make_robust_loss(RobustLoss loss, double scale)
{
	return make_loss(to_string(loss), scale);
}

bool robust_loss_is_valid(RobustLoss loss, double scale, std::string* why)
{
	try
	{
		make_robust_loss(loss, scale);
		return true;
	}
	catch (const std::invalid_argument& e)
	{
		if (why) *why = e.what();
		return false;
	}
}
}  // namespace swba::apps

// swba_online_slam: the sliding-window estimator fed step by step from an MRPT rawlog, as an online
// application would feed it (see OnlineSlamApp.h). Usage: swba_online_slam --help
#include <exception>
#include <iostream>

#include "OnlineSlamApp.h"

int main(int argc, char** argv)
{
	try
	{
		OnlineSlamApp app;
		if (!app.initialize(argc, argv)) return 0;  // --help
		app.run();
		return 0;
	}
	catch (const std::exception& e)
	{
		std::cerr << "swba_online_slam: error: " << e.what() << "\n";
		return 1;
	}
}

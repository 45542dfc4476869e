// bin/tailor: the command line is a library function (problems/cli/run_cli.hpp).
#include "problems/cli/run_cli.hpp"

int main(int argc, char** argv) { return tailor::run_cli(argc, argv); }

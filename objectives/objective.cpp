#include "objectives/objective.hpp"

#include "adjoint/derivative_check.hpp"

// stats.hpp — fixture for scripts/check_floors (see fit.hpp).
#pragma once

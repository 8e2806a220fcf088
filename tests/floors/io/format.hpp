// format.hpp — fixture for scripts/check_floors (see writer.hpp).
#pragma once

#include <string>  // fine

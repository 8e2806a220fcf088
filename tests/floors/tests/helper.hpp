// helper.hpp — fixture for scripts/check_floors: a file outside the floors.
#pragma once

// box.hpp — fixture for scripts/check_floors (see vec.hpp).
#pragma once

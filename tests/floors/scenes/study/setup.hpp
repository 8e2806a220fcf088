// setup.hpp — fixture for scripts/check_floors (see scene.hpp).
#pragma once

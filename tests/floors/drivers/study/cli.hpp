// cli.hpp — fixture for scripts/check_floors (see main.cpp).
#pragma once

// lifetime.hpp — fixture for scripts/check_floors (see bindings.cpp).
#pragma once

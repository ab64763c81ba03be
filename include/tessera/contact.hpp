#pragma once
// Module header for contact/. Owners add their headers here as they land.
#include "core.hpp"
#include "contact/subcontact_set.hpp"

#pragma once
// Module header for contact/. Owners add their headers here as they land.
#include "core.hpp"
#include "contact/concepts.hpp"
#include "contact/detected_contacts.hpp"
#include "contact/detected/params.hpp"
#include "contact/face_contacts.hpp"
#include "contact/material_table.hpp"
#include "contact/platen.hpp"
#include "contact/kinematics.hpp"
#include "contact/stiffness_bound.hpp"

#pragma once
// Sub-contact kinematics (namespace tessera::contact::kinematics) live in core/, below both the
// contact sets and the contact laws that share them: see core/contact_kinematics.hpp.
#include "../core/contact_kinematics.hpp"

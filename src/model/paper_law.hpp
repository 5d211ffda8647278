// SPDX-License-Identifier: GPL-3.0-or-later
// paper_law.hpp -- the embedded default: Leine & Winandy's sequential impact law for the
// 3-ball Newton's cradle (SPEC section 2), with its identities, single impacts, the five
// classical outcomes, and every claim. proofs/newton3/law.json states the same law; a test
// proves the two identical.
#pragma once

#include "model/law.hpp"

namespace impactcert {

Law paper_law();

} // namespace impactcert

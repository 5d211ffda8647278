// SPDX-License-Identifier: GPL-3.0-or-later
// scene_common.hpp -- internal to scene.cpp and scene3d.cpp: what scenes in the plane and in
// space share once their contacts are found.
//
// Contract:
//   - contact_values: each contact's mu and restitution, its own, else its pair's ("pairs", by
//     the names of two bodies or boundaries), else the scene's ("friction", "restitution");
//     InputError naming where a value was given when mu < 0 or the restitution is outside
//     [0, 1], and naming the contact when some contacts have a restitution and it has none. The
//     contacts' names: "a/b", a second one of a pair "a/b #2".
//   - check_scene_mechanics: make_mechanics on the scene's system, its InputError said in the
//     scene's terms (its place, the contacts it has); dependent columns are allowed here.
//   - two_ends: the indices of the two bodies or boundaries named at `names`; InputError naming
//     the place unless there are two known names, of two bodies or of a body and a boundary.
//   - read_listed: a listed contact's ends (a boundary always first: `flip` tells the caller to
//     turn the given normal round), mu and restitution; its point and normal are the caller's.
#pragma once

#include "base/json_read.hpp"
#include "model/system.hpp"

#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace impactcert::scene_common {

struct ContactRef {
    int i = -1, j = -1;      // body indices; a boundary -(k + 2)
    std::string name, path;  // "a/b", where it was found or listed
    std::optional<Rational> mu, e; // given on a listed contact
};

struct ContactValues {
    std::vector<Rational> mu;          // 0 where none is given (no friction)
    std::vector<Rational> restitution; // meaningful when any_restitution
    bool any_restitution = false;
    std::vector<std::string> names;
};

ContactValues contact_values(const json_read::ReadJson& doc, const std::map<std::string, int>& index,
                             const std::vector<ContactRef>& contacts);
void check_scene_mechanics(const json_read::ReadJson& doc, const System& out);

std::pair<int, int> two_ends(const json_read::ReadJson& names, const std::string& path,
                             const std::map<std::string, int>& index, const std::string& what);

struct Listed {
    int i = -1, j = -1;
    bool flip = false;
    std::optional<Rational> mu, e;
};
Listed read_listed(const json_read::ReadJson& jc, const std::string& path, const std::map<std::string, int>& index);

} // namespace impactcert::scene_common

// What the repair's tests share.
#pragma once

#include "plimsoll/repair/physics_solid.h"

#include <gtest/gtest.h>

/// Skips a test of the repair in a build without CGAL (PLIMSOLL_WITH_CGAL=OFF).
#define SKIP_WITHOUT_REPAIR() \
    if (!::plimsoll::repairAvailable()) GTEST_SKIP() << "built without CGAL: no mesh repair"

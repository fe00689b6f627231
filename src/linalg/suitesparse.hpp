// Shared by the SuiteSparse backends: our int64_t index arrays go to them as
// SuiteSparse_long without a copy.
#pragma once
#include <SuiteSparse_config.h>

#include <cstdint>
#include <type_traits>

static_assert(std::is_same<SuiteSparse_long, int64_t>::value, "SuiteSparse_long must be int64_t");

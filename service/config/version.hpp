#pragma once
// The slosh version: generated for api/ (slosh/version.hpp), which the service links.
#include "slosh/version.hpp"

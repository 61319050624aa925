#include "continuation/arclength.hpp"

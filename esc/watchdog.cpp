#include "esc/watchdog.hpp"

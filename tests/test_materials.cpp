#include "materials_scenes.h"

// placeholder: being written
#include "fricrom/fe_model.h"

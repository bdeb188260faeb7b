// Planted: a file every layer shares that names a layer (the SPH gains).
#pragma once

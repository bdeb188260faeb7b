// A file that breaks every rule once; the lint must reject it.
#include <iostream>
inline double scale(double v) { return v * 1.5; }
inline int* make() { return new int(3); }
inline void fail() { throw 1; }

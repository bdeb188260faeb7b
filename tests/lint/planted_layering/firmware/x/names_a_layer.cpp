// Planted: a firmware file that names a physical layer.
bool metaballs_on = true;

// Debian's three.js (libjs-three) and its orbit controls, read into the program when it is built,
// so a report embeds them and its 3D view works from a file opened offline: nothing is fetched.
#pragma once

namespace dg::host {

const char* three_js();             // three.min.js
const char* three_orbit_controls();  // examples/js/controls/OrbitControls.js (THREE.OrbitControls)

}  // namespace dg::host

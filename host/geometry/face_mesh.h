// A trimmed face's triangles: its surface's grid mesh cut at the face's loops.
#pragma once
#include "host/geometry/tessellate.h"
#include "host/geometry/trimmed_face.h"

namespace dg::host {

// `grid` is the face surface's uniform grid mesh (vertex (i, j) at i * nv + j, two triangles a
// cell, x following i and y following j). Triangles inside the face are kept whole; a triangle a
// loop crosses once (the loop entering through one edge and leaving through another) is split
// along the loop and its parts inside the face kept, with new vertices on the face's surface where
// the loop crosses its edges and at the loop's corners inside it, so the mesh ends on the trims.
// A triangle crossed in a way the cut cannot untangle (a run of the loop that leaves by the
// domain's edge, a piece that cannot be triangulated) is kept whole when its centre is inside, as
// before. Appends to `out`.
void append_face_mesh(const TrimmedFace& face, const Mesh& grid, int nu, int nv, Mesh& out);

}  // namespace dg::host

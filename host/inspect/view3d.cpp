// The 3D view: the points and their colours, and the surface's mesh, as arrays in the page, drawn
// by Debian's three.js (embedded in the page with its orbit controls, nothing fetched) in an
// orthographic view that mouse drags turn, shift- or right-drags move, and the wheel or + and -
// zoom (0 resets; the page's #zoom=F opens it zoomed). Each drawing leaves the numbers of points
// drawn and on the canvas, the zoom and the surface's triangles in the canvas's data-drawn,
// data-visible, data-zoom and data-triangles attributes, where a browser test can read them.
#include "host/inspect/view3d.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "host/inspect/deviation_map.h"
#include "host/inspect/three_js.h"

namespace dg::host {

std::string view3d_html(const Inspection& inspection, const ColourScale& scale, const Mesh* surface, size_t max_points) {
  const std::vector<PointDeviation>& all = inspection.points;
  if (all.empty()) return "";
  double range = scale.range_mm;
  if (!(range > 0)) {
    for (const PointDeviation& d : all) range = d.beyond_edge ? range : std::max(range, std::fabs(d.distance));
  }
  if (!(range > 0)) range = 1e-3;
  const size_t stride = std::max<size_t>(1, (all.size() + max_points - 1) / std::max<size_t>(1, max_points));
  std::string xyz = "[", colours = "[";
  char buffer[96];
  bool first = true;
  for (size_t k = 0; k < all.size(); k += stride) {
    const PointDeviation& d = all[k];
    // Beyond the surface's edge a point's distance is to the edge: grey, as on the maps.
    const Rgb c = d.beyond_edge ? kMutedColour : scale_colour(scale, range, d.distance);
    std::snprintf(buffer, sizeof buffer, "%s%.4f,%.4f,%.4f", first ? "" : ",", d.point.x, d.point.y, d.point.z);
    xyz += buffer;
    std::snprintf(buffer, sizeof buffer, "%s%.4f,%.4f,%.4f", first ? "" : ",", c.r / 255.0, c.g / 255.0, c.b / 255.0);
    colours += buffer;
    first = false;
  }
  xyz += "]";
  colours += "]";
  std::string surface_xyz = "[", surface_triangles = "[";
  if (surface) {
    first = true;
    for (const Point3& q : surface->vertices) {
      std::snprintf(buffer, sizeof buffer, "%s%.3f,%.3f,%.3f", first ? "" : ",", q.x, q.y, q.z);
      surface_xyz += buffer;
      first = false;
    }
    first = true;
    for (const auto& t : surface->triangles) {
      std::snprintf(buffer, sizeof buffer, "%s%u,%u,%u", first ? "" : ",", t[0], t[1], t[2]);
      surface_triangles += buffer;
      first = false;
    }
  }
  surface_xyz += "]";
  surface_triangles += "]";
  // The script: the points centred on their bounding box, in a camera whose view at zoom 1 holds
  // the box's bounding sphere, looking down at the part from the front and to the right (z up);
  // the surface translucent and drawn after them without hiding them (it writes no depth), since
  // the points lie on it to within their deviations.
  // Without WebGL the figure says so instead of failing on the page's console.
  return "<div id=\"view3d\" tabindex=\"0\" style=\"max-width:100%\"></div>\n"
         "<p id=\"view3d-help\" style=\"font-size:0.85em;color:#333\">Drag to turn, shift-drag or right-drag to move, "
         "wheel or + and - to zoom, 0 to reset.</p>\n<script>\n" +
         std::string(three_js()) + "\n</script>\n<script>\n" + three_orbit_controls() +
         "\n</script>\n<script>\n(function(){\nconst p=" + xyz + ";\nconst c=" + colours + ";\nconst sv=" + surface_xyz +
         ";\nconst st=" + surface_triangles + ";\n" +
         R"JS(const box=document.getElementById('view3d'),W=900,H=560,n=p.length/3;
const probe=document.createElement('canvas');
if(!window.WebGLRenderingContext||!(probe.getContext('webgl')||probe.getContext('experimental-webgl'))){
box.textContent='The 3D view needs WebGL, which this browser does not offer.';return;}
let lo=[1/0,1/0,1/0],hi=[-1/0,-1/0,-1/0];
for(let i=0;i<n;i++)for(let a=0;a<3;a++){lo[a]=Math.min(lo[a],p[3*i+a]);hi[a]=Math.max(hi[a],p[3*i+a]);}
const m=[0,1,2].map(a=>(lo[a]+hi[a])/2),r=Math.max(1e-9,Math.hypot(hi[0]-lo[0],hi[1]-lo[1],hi[2]-lo[2])/2);
const xyz=new Float32Array(3*n);for(let i=0;i<3*n;i++)xyz[i]=p[i]-m[i%3];
const geometry=new THREE.BufferGeometry();
geometry.setAttribute('position',new THREE.BufferAttribute(xyz,3));
geometry.setAttribute('color',new THREE.BufferAttribute(new Float32Array(c),3));
const size=Math.max(2,Math.min(8,0.9*Math.min(W,H)/Math.sqrt(n)));
const scene=new THREE.Scene();
scene.add(new THREE.Points(geometry,new THREE.PointsMaterial({size:size,sizeAttenuation:false,vertexColors:THREE.VertexColors})));
if(st.length){const s=new Float32Array(sv.length);for(let i=0;i<sv.length;i++)s[i]=sv[i]-m[i%3];
const surface=new THREE.BufferGeometry();surface.setAttribute('position',new THREE.BufferAttribute(s,3));surface.setIndex(st);
surface.computeVertexNormals();
scene.add(new THREE.Mesh(surface,new THREE.MeshLambertMaterial({color:0xaab1bf,transparent:true,opacity:0.55,side:THREE.DoubleSide,depthWrite:false})));
scene.add(new THREE.AmbientLight(0xffffff,0.6));const light=new THREE.DirectionalLight(0xffffff,0.5);light.position.set(0.3,-0.6,1);scene.add(light);}
const a=r/0.9,camera=new THREE.OrthographicCamera(-a*W/H,a*W/H,a,-a,-20*r,20*r);
camera.up.set(0,0,1);camera.position.set(0.55*r,-1.1*r,0.95*r);camera.lookAt(0,0,0);
const renderer=new THREE.WebGLRenderer({antialias:true,preserveDrawingBuffer:true});
renderer.setClearColor(0xf4f5f8,1);renderer.setSize(W,H);
const v=renderer.domElement;v.style.maxWidth='100%';v.style.height='auto';v.style.border='1px solid #ccc';v.style.cursor='grab';
box.appendChild(v);
const controls=new THREE.OrbitControls(camera,v);
controls.screenSpacePanning=true;controls.minZoom=0.5;controls.maxZoom=50;controls.zoomSpeed=1.5;
const h=/zoom=([0-9.]+)/.exec(location.hash);
if(h){camera.zoom=Math.max(0.5,Math.min(50,+h[1]));camera.updateProjectionMatrix();}
controls.saveState();
const q=new THREE.Vector3();
function draw(){renderer.render(scene,camera);let seen=0;
for(let i=0;i<n;i++){q.set(xyz[3*i],xyz[3*i+1],xyz[3*i+2]).project(camera);if(Math.abs(q.x)<=1&&Math.abs(q.y)<=1)seen++;}
v.dataset.drawn=n;v.dataset.visible=seen;v.dataset.zoom=camera.zoom;v.dataset.triangles=st.length/3;}
controls.addEventListener('change',draw);
box.addEventListener('keydown',e=>{
if(e.key==='+'||e.key==='='){camera.zoom=Math.min(50,camera.zoom*1.25);}
else if(e.key==='-'){camera.zoom=Math.max(0.5,camera.zoom*0.8);}
else if(e.key==='0'){controls.reset();camera.zoom=1;}
else return;
camera.updateProjectionMatrix();draw();e.preventDefault();});
draw();})();
</script>
)JS";
}

}  // namespace dg::host

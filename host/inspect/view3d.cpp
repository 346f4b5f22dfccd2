// The 3D view: points and colours as JSON arrays in the page, drawn far to near on a 2D canvas in
// an orthographic projection that mouse drags and arrow keys turn, shift-drags move, and the wheel
// or + and - zoom about the cursor (the page's #zoom=F opens it zoomed). Each drawing leaves the
// numbers of points drawn and on the canvas, and the zoom, in the canvas's data-drawn,
// data-visible and data-zoom attributes, where a browser test can read them.
#include "host/inspect/view3d.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "host/inspect/deviation_map.h"

namespace dg::host {

std::string view3d_html(const Inspection& inspection, const ColourScale& scale, size_t max_points) {
  const std::vector<PointDeviation>& all = inspection.points;
  if (all.empty()) return "";
  double range = scale.range_mm;
  if (!(range > 0)) {
    for (const PointDeviation& d : all) range = std::max(range, std::fabs(d.distance));
  }
  if (!(range > 0)) range = 1e-3;
  const size_t stride = std::max<size_t>(1, (all.size() + max_points - 1) / std::max<size_t>(1, max_points));
  std::string xyz = "[", colours = "[";
  char buffer[96];
  bool first = true;
  for (size_t k = 0; k < all.size(); k += stride) {
    const PointDeviation& d = all[k];
    const Rgb c = scale_colour(scale, range, d.distance);
    std::snprintf(buffer, sizeof buffer, "%s%.4f,%.4f,%.4f", first ? "" : ",", d.point.x, d.point.y, d.point.z);
    xyz += buffer;
    std::snprintf(buffer, sizeof buffer, "%s\"#%02x%02x%02x\"", first ? "" : ",", c.r, c.g, c.b);
    colours += buffer;
    first = false;
  }
  xyz += "]";
  colours += "]";
  // The script: centre and scale the points to the canvas, then draw each as a small square,
  // farthest first, after turning them by yaw about z and tilting them by pitch about x (0: seen
  // from above, x right and y up; pi/2: seen from the front, z up). Heights are drawn to scale.
  return "<canvas id=\"view3d\" width=\"900\" height=\"560\" tabindex=\"0\" "
         "style=\"background:#f4f5f8;border:1px solid #ccc;cursor:grab;max-width:100%\"></canvas>\n"
         "<script>\n(function(){\nconst p=" + xyz + ";\nconst c=" + colours + ";\n" +
         R"JS(const v=document.getElementById('view3d'),g=v.getContext('2d'),n=p.length/3;
let lo=[1/0,1/0,1/0],hi=[-1/0,-1/0,-1/0];
for(let i=0;i<n;i++)for(let a=0;a<3;a++){lo[a]=Math.min(lo[a],p[3*i+a]);hi[a]=Math.max(hi[a],p[3*i+a]);}
const m=[0,1,2].map(a=>(lo[a]+hi[a])/2),r=Math.max(1e-9,Math.hypot(hi[0]-lo[0],hi[1]-lo[1],hi[2]-lo[2])/2);
const h=/zoom=([0-9.]+)/.exec(location.hash);
let yaw=-0.6,pitch=1.0,zoom=h?Math.max(0.5,Math.min(50,+h[1])):1,pan=[0,0];const order=new Array(n),q=new Float64Array(3*n);
function draw(){const s=zoom*0.9*Math.min(v.width,v.height)/(2*r),cy=Math.cos(yaw),sy=Math.sin(yaw),cp=Math.cos(pitch),sp=Math.sin(pitch);
let seen=0;
for(let i=0;i<n;i++){const x=p[3*i]-m[0],y=p[3*i+1]-m[1],z=p[3*i+2]-m[2];const X=cy*x-sy*y,Y=sy*x+cy*y;
q[3*i]=v.width/2+pan[0]+s*X;q[3*i+1]=v.height/2+pan[1]-s*(Y*cp+z*sp);q[3*i+2]=z*cp-Y*sp;order[i]=i;
if(q[3*i]>=0&&q[3*i]<v.width&&q[3*i+1]>=0&&q[3*i+1]<v.height)seen++;}
order.sort((a,b)=>q[3*a+2]-q[3*b+2]);g.clearRect(0,0,v.width,v.height);
const d=Math.max(2,Math.min(8*Math.sqrt(zoom),s*2*r/Math.sqrt(n)));
for(const i of order){g.fillStyle=c[i];g.fillRect(q[3*i]-d/2,q[3*i+1]-d/2,d,d);}
g.fillStyle='#333';g.font='13px sans-serif';
g.fillText('drag to turn, shift-drag to move, wheel or + and - to zoom ('+zoom.toFixed(1)+'x), 0 to reset',10,v.height-10);
v.dataset.drawn=n;v.dataset.visible=seen;v.dataset.zoom=zoom;}
function zoom_at(f,cx,cy){const z=Math.max(0.5,Math.min(50,zoom*f)),k=z/zoom;
pan=[(pan[0]-(cx-v.width/2))*k+(cx-v.width/2),(pan[1]-(cy-v.height/2))*k+(cy-v.height/2)];zoom=z;draw();}
let drag=null;v.addEventListener('mousedown',e=>{drag=[e.clientX,e.clientY,e.shiftKey];});
window.addEventListener('mouseup',()=>{drag=null;});
window.addEventListener('mousemove',e=>{if(!drag)return;const dx=e.clientX-drag[0],dy=e.clientY-drag[1];
if(drag[2]){pan=[pan[0]+dx,pan[1]+dy];}else{yaw+=dx*0.01;pitch=Math.max(0,Math.min(Math.PI,pitch+dy*0.01));}
drag=[e.clientX,e.clientY,drag[2]];draw();});
v.addEventListener('wheel',e=>{const b=v.getBoundingClientRect();
zoom_at(Math.exp(-e.deltaY*0.0015),(e.clientX-b.left)*v.width/b.width,(e.clientY-b.top)*v.height/b.height);e.preventDefault();},{passive:false});
v.addEventListener('keydown',e=>{const k={ArrowLeft:[-0.1,0],ArrowRight:[0.1,0],ArrowUp:[0,-0.1],ArrowDown:[0,0.1]}[e.key];
if(e.key==='+'||e.key==='='){zoom_at(1.25,v.width/2,v.height/2);e.preventDefault();return;}
if(e.key==='-'){zoom_at(0.8,v.width/2,v.height/2);e.preventDefault();return;}
if(e.key==='0'){zoom=1;pan=[0,0];yaw=-0.6;pitch=1.0;draw();e.preventDefault();return;}
if(!k)return;yaw+=k[0];pitch=Math.max(0,Math.min(Math.PI,pitch+k[1]));draw();e.preventDefault();});
draw();})();
</script>
)JS";
}

}  // namespace dg::host

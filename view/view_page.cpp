#include "view/view_page.h"

#include <fstream>
#include <sstream>

#include "core/finding.h"
#include "export/mesh/collision_meshes.h"
#include "export/mesh/mesh_export.h"

namespace mbx {

namespace {

std::string read_script(const std::string& relative) {
    const std::string path = std::string(MBX_THREE_JS_DIR) + "/" + relative;
    std::ifstream in(path, std::ios::binary);
    if (!in)
        throw Error(MBX_ERROR_IO, Subject::model("view"),
                    "cannot read three.js at '" + path + "': install Debian's libjs-three (the page inlines it)", path);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

std::string base64(const std::string& bytes) {
    static const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((bytes.size() + 2) / 3 * 4);
    size_t i = 0;
    for (; i + 2 < bytes.size(); i += 3) {
        const unsigned v = unsigned(uint8_t(bytes[i])) << 16 | unsigned(uint8_t(bytes[i + 1])) << 8 | uint8_t(bytes[i + 2]);
        out += {digits[v >> 18], digits[v >> 12 & 63], digits[v >> 6 & 63], digits[v & 63]};
    }
    if (i + 1 == bytes.size()) {
        const unsigned v = unsigned(uint8_t(bytes[i])) << 16;
        out += {digits[v >> 18], digits[v >> 12 & 63], '=', '='};
    } else if (i + 2 == bytes.size()) {
        const unsigned v = unsigned(uint8_t(bytes[i])) << 16 | unsigned(uint8_t(bytes[i + 1])) << 8;
        out += {digits[v >> 18], digits[v >> 12 & 63], digits[v >> 6 & 63], '='};
    }
    return out;
}

// A JSON string literal safe inside a <script> element ("</" never appears).
std::string js_string(const std::string& s) {
    std::string out = "\"";
    for (char c : s) {
        if (c == '"' || c == '\\') out += '\\', out += c;
        else if (c == '<') out += "\\u003c";
        else if (uint8_t(c) < 0x20) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", unsigned(c));
            out += buf;
        } else out += c;
    }
    return out + "\"";
}

std::string motion_json(const PosedTrajectory& motion) {
    std::ostringstream s;
    s.precision(7);
    s << "{\"nodes\":[";
    for (size_t k = 0; k < motion.nodes.size(); ++k) s << (k ? "," : "") << js_string(motion.nodes[k]);
    s << "],\"times\":[";
    for (size_t k = 0; k < motion.times.size(); ++k) s << (k ? "," : "") << motion.times[k];
    s << "],\"poses\":[";
    for (size_t k = 0; k < motion.poses.size(); ++k) s << (k ? "," : "") << motion.poses[k];
    s << "]}";
    return s.str();
}

// The page's own script. It runs after three.js and its GLTF loader and
// orbit controls (examples/js, the global THREE namespace of r111).
const char* kPageScript = R"JS(
(function () {
  const status = document.getElementById('mbx-status');
  const bytes = Uint8Array.from(atob(MBX_SCENE), c => c.charCodeAt(0));
  const renderer = new THREE.WebGLRenderer({antialias: true, preserveDrawingBuffer: true});
  renderer.setPixelRatio(window.devicePixelRatio);
  renderer.setSize(window.innerWidth, window.innerHeight);
  document.body.appendChild(renderer.domElement);
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0xf4f4f4);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x808080, 0.9));
  const sun = new THREE.DirectionalLight(0xffffff, 0.6);
  sun.position.set(1, -2, 3);
  scene.add(sun);
  // CAD is z-up; so is this camera.
  const camera = new THREE.PerspectiveCamera(40, window.innerWidth / window.innerHeight, 1e-3, 1e4);
  camera.up.set(0, 0, 1);
  const controls = new THREE.OrbitControls(camera, renderer.domElement);
  const nodes = [];
  let t0 = null, drawn = 0;

  function frameAt(t) {
    const times = MBX_MOTION.times;
    let lo = 0, hi = times.length - 1;
    while (lo < hi) { const mid = (lo + hi + 1) >> 1; if (times[mid] <= t) lo = mid; else hi = mid - 1; }
    return lo;
  }
  function pose(frame) {
    const p = MBX_MOTION.poses, n = nodes.length;
    for (let k = 0; k < n; ++k) {
      if (!nodes[k]) continue;
      const o = (frame * n + k) * 7;
      nodes[k].position.set(p[o], p[o + 1], p[o + 2]);
      nodes[k].quaternion.set(p[o + 4], p[o + 5], p[o + 6], p[o + 3]);
    }
  }
  function countDrawn() {
    // Pixels that differ from the background: a headless check that the
    // model, not an empty canvas, is on screen.
    const gl = renderer.getContext(), w = gl.drawingBufferWidth, h = gl.drawingBufferHeight;
    const px = new Uint8Array(w * h * 4);
    gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px);
    let n = 0;
    for (let i = 0; i < px.length; i += 4)
      if (Math.abs(px[i] - 0xf4) + Math.abs(px[i + 1] - 0xf4) + Math.abs(px[i + 2] - 0xf4) > 24) ++n;
    return n / (w * h);
  }
  function animate(now) {
    requestAnimationFrame(animate);
    if (MBX_MOTION && MBX_MOTION.times.length > 1) {
      if (t0 === null) t0 = now;
      const times = MBX_MOTION.times, span = times[times.length - 1] - times[0];
      pose(frameAt(times[0] + ((now - t0) / 1000) % span));
    }
    controls.update();
    renderer.render(scene, camera);
    if (!drawn) {
      drawn = countDrawn();
      status.textContent = 'nodes=' + nodes.filter(x => x).length + ' frames=' + (MBX_MOTION ? MBX_MOTION.times.length : 0) +
                           ' drawn=' + drawn.toFixed(4) + ' collision=' + status.dataset.collision;
      status.dataset.drawn = drawn;
    }
  }
  new THREE.GLTFLoader().parse(bytes.buffer, '', function (gltf) {
    const root = gltf.scene;
    scene.add(root);
    root.updateMatrixWorld(true);
    // Collision shapes ride under their bodies' nodes; hidden until asked for.
    const collision = MBX_COLLISION.map(name => root.getObjectByName(name)).filter(x => x);
    const toggle = document.getElementById('mbx-collision');
    const showCollision = () => collision.forEach(node => { node.visible = toggle.checked; });
    // view.html#collision opens with them shown (a link can ask for them).
    if (toggle) {
      toggle.checked = location.hash.indexOf('collision') >= 0;
      toggle.addEventListener('change', showCollision);
      showCollision();
    }
    status.dataset.collision = collision.length;
    if (MBX_MOTION) {
      for (const name of MBX_MOTION.nodes) {
        const node = root.getObjectByName(name);
        // Poses are world poses: hang the body straight under the root.
        if (node) root.attach(node);
        nodes.push(node || null);
      }
      pose(0);
    }
    const box = new THREE.Box3().setFromObject(root), size = box.getSize(new THREE.Vector3()).length() || 1;
    const centre = box.getCenter(new THREE.Vector3());
    camera.position.copy(centre).add(new THREE.Vector3(0.6, -0.95, 0.55).multiplyScalar(size));
    camera.near = size / 1000, camera.far = size * 100;
    camera.updateProjectionMatrix();
    controls.target.copy(centre);
    requestAnimationFrame(animate);
  }, function (error) { status.textContent = 'error: ' + error; });
  window.addEventListener('resize', function () {
    camera.aspect = window.innerWidth / window.innerHeight;
    camera.updateProjectionMatrix();
    renderer.setSize(window.innerWidth, window.innerHeight);
  });
})();
)JS";

std::string collision_list(const std::vector<std::string>& names) {
    std::string out;
    for (size_t k = 0; k < names.size(); ++k) out += (k ? "," : "") + js_string(names[k]);
    return out;
}

std::string escape_html(const std::string& s) {
    std::string out;
    for (char c : s) {
        if (c == '<') out += "&lt;";
        else if (c == '>') out += "&gt;";
        else if (c == '&') out += "&amp;";
        else out += c;
    }
    return out;
}

}  // namespace

std::string view_page(const std::string& title, const std::string& glb, const PosedTrajectory* motion,
                      const std::vector<std::string>& collision_nodes) {
    const std::string three = read_script("three.min.js"), loader = read_script("examples/js/loaders/GLTFLoader.js"),
                      controls = read_script("examples/js/controls/OrbitControls.js");
    std::ostringstream page;
    page << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>" << escape_html(title) << "</title>\n"
         << "<style>html,body{margin:0;height:100%;overflow:hidden;font:13px sans-serif}"
         << "#mbx-status{position:absolute;left:8px;top:6px;color:#555}"
         << "#mbx-collision-label{position:absolute;right:8px;top:6px;color:#555}</style></head>\n<body>\n"
         << "<div id=\"mbx-status\">loading</div>\n"
         << (collision_nodes.empty() ? ""
                                     : "<label id=\"mbx-collision-label\"><input type=\"checkbox\" id=\"mbx-collision\">"
                                       " collision shapes</label>\n")
         << "<script>\n" << three << "\n</script>\n<script>\n" << loader << "\n</script>\n<script>\n" << controls
         << "\n</script>\n<script>\nconst MBX_SCENE = \"" << base64(glb) << "\";\nconst MBX_MOTION = "
         << (motion && motion->frames() ? motion_json(*motion) : std::string("null")) << ";\nconst MBX_COLLISION = ["
         << collision_list(collision_nodes) << "];\n"
         << kPageScript << "</script>\n</body></html>\n";
    return page.str();
}

OutputFiles view_files(ExportModel& model, const std::string& trajectory_csv) {
    OutputFiles scene;
    const bool collision = !model.settings().contact.empty();
    export_scene(model, scene, collision);
    std::vector<std::string> collision_nodes;
    if (collision)
        for (const CollisionMesh& c : collision_meshes(model, "view")) collision_nodes.push_back(c.node);
    if (scene.empty())
        throw Error(MBX_ERROR_INVALID_INPUT, Subject::model(model.settings().model_name),
                    "nothing to show: no body of the model has a mesh");
    PosedTrajectory motion;
    if (!trajectory_csv.empty()) motion = pose_trajectory(model, trajectory_csv);
    return {OutputFile{"view.html", view_page(model.settings().model_name, scene.front().contents,
                                              trajectory_csv.empty() ? nullptr : &motion, collision_nodes)}};
}

}  // namespace mbx

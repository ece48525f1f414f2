// OpenVDB peer of `sim render` (svo_sim project, issue 14 part 2).
//
// What it is: an independent renderer of a bare MagicaVoxel model that shares no code with the
// project. It reads the .vox itself (own RIFF chunk reader, own scene-graph walk and voxel
// placement), keeps the surface voxels (those with an empty face neighbour: the project stores
// only those, and an interior voxel can only be reached through a solid face neighbour or from
// an origin inside it, so the first hit of a ray from an empty cell is the same), puts them as
// active voxels into an OpenVDB 10 BoolGrid whose index space is the model's own voxel space
// (identity transform: voxel (i, j, k) is the cell [i, i+1) x [j, j+1) x [k, k+1) as
// OpenVDB's math::DDA sees it, floor-based), and traces every pixel with OpenVDB's traversal:
// tools::VolumeRayIntersector (hierarchical DDA over the tree's nodes, march() span by span)
// and, inside each span of active leaf nodes, math::DDA<Ray, 0> over voxels until an active
// voxel. The hit is that voxel; t is the DDA's entry time (the ray starts at t = 0).
//
// Camera contract (docs/render.md §2, the same formulas and operation order as the project,
// so the f64 rays are bit-identical): pinhole
//   forward = normalise(look - eye), right = normalise(forward x up), up' = right x forward,
//   tau = tan(fov * (pi/180) * 0.5), a = W/H,
//   u = ((2(i + 0.5))/W - 1) * tau * a,  v = (1 - (2(j + 0.5))/H) * tau,
//   d = normalise((forward + right*u) + up'*v),  o = eye;
// orthographic of view width w: hw = w*0.5, hh = (hw*H)/W,
//   u = ((2(i + 0.5))/W - 1) * hw, v = (1 - (2(j + 0.5))/H) * hh,
//   o = (eye + right*u) + up'*v, d = forward;
// normalise(x) = x * (1/sqrt((x.x*x.x + x.y*x.y) + x.z*x.z)); every component of d gets + 0.0
// (-0 becomes +0). Build with -ffp-contract=off (no fused multiply-add).
//
// Output: a dump in the format of `sim render --dump-hits` (SVOMHIT1, docs/render.md §5)
// with face and colour left 0 (the peer reports voxel and t only), and on stdout lines
// `solid_min x y z`, `solid_max x y z`, `voxels N`, `surface N`, `trace_seconds S` and
// `trace_median_seconds S` (best and median of REPEAT timed renders of all rays on THREADS
// threads, after one untimed warm-up render).
//
// Speed: written the way OpenVDB documents its fast path (docs/render.md §7 measures each
// point): one ConstUnsafeAccessor per thread (getConstUnsafeAccessor(): not registered with
// the tree), one shallow copy of the VolumeRayIntersector per thread (sharing the master's
// tree), the worker threads made before the timed region, one untimed warm-up render, -O3.
//
// Usage: peer MODEL.vox OUT.bin W H ex ey ez lx ly lz ux uy uz (pinhole FOV | ortho WIDTH)
//        [THREADS [REPEAT]]
// Built by tests/openvdb_peer.rs: g++ -std=c++17 -O3 -DNDEBUG -ffp-contract=off peer.cpp
//        -lopenvdb -ltbb -lpthread

#include <openvdb/openvdb.h>
#include <openvdb/math/DDA.h>
#include <openvdb/math/Ray.h>
#include <openvdb/tools/RayIntersector.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <unordered_set>
#include <vector>

namespace {

[[noreturn]] void fail(const std::string& what) { throw std::runtime_error(what); }

// ---------------------------------------------------------------- .vox reading

struct Reader {
    const std::vector<uint8_t>& b;
    size_t pos, end;
    int32_t i32() {
        if (pos + 4 > end) fail("truncated chunk");
        int32_t v;
        std::memcpy(&v, &b[pos], 4);
        pos += 4;
        return v;
    }
    std::string str() {
        int32_t n = i32();
        if (n < 0 || pos + size_t(n) > end) fail("bad string");
        std::string s(reinterpret_cast<const char*>(&b[pos]), size_t(n));
        pos += size_t(n);
        return s;
    }
    std::map<std::string, std::string> dict() {
        int32_t n = i32();
        if (n < 0) fail("bad dict");
        std::map<std::string, std::string> d;
        for (int32_t k = 0; k < n; ++k) {
            std::string key = str();
            d[key] = str();
        }
        return d;
    }
};

struct Model {
    int sx = 0, sy = 0, sz = 0;
    std::vector<std::array<int, 3>> voxels;
};

struct Node {
    enum Kind { Transform, Group, Shape } kind = Group;
    std::map<std::string, std::string> attrs;
    std::map<std::string, std::string> frame0;  // nTRN first frame
    int child = -1, layer = -1;                 // nTRN
    std::vector<int> children;                  // nGRP
    int model = -1;                             // nSHP first model
};

struct Affine {
    int r[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    long t[3] = {0, 0, 0};
    Affine then(const Affine& in) const {  // this o in
        Affine o;
        for (int i = 0; i < 3; ++i) {
            o.t[i] = t[i];
            for (int j = 0; j < 3; ++j) {
                o.r[i][j] = 0;
                for (int k = 0; k < 3; ++k) o.r[i][j] += r[i][k] * in.r[k][j];
                o.t[i] += long(r[i][j]) * in.t[j];
            }
        }
        return o;
    }
};

bool hidden(const std::map<std::string, std::string>& a) {
    auto it = a.find("_hidden");
    return it != a.end() && it->second == "1";
}

Affine frame_affine(const std::map<std::string, std::string>& f) {
    Affine a;
    auto r = f.find("_r");
    if (r != f.end()) {
        int byte = std::stoi(r->second);
        int c0 = byte & 3, c1 = (byte >> 2) & 3;
        if (c0 > 2 || c1 > 2 || c0 == c1) fail("bad _r");
        int c2 = 3 - c0 - c1;
        int cols[3] = {c0, c1, c2};
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) a.r[i][j] = 0;
            a.r[i][cols[i]] = (byte & (1 << (4 + i))) ? -1 : 1;
        }
    }
    auto t = f.find("_t");
    if (t != f.end()) {
        long x, y, z;
        if (std::sscanf(t->second.c_str(), "%ld %ld %ld", &x, &y, &z) != 3) fail("bad _t");
        a.t[0] = x;
        a.t[1] = y;
        a.t[2] = z;
    }
    return a;
}

long floor_div2(long v) { return v >= 0 ? v / 2 : -((-v + 1) / 2); }

// Every visible voxel of the composed scene, in MagicaVoxel coordinates.
std::vector<std::array<long, 3>> read_vox(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) fail("cannot open " + path);
    std::vector<uint8_t> b((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (b.size() < 20 || std::memcmp(b.data(), "VOX ", 4) != 0) fail("not a .vox file");
    Reader main{b, 8, b.size()};
    char id[5] = {0};
    std::memcpy(id, &b[8], 4);
    if (std::string(id) != "MAIN") fail("no MAIN chunk");
    main.pos = 12;
    int32_t main_content = main.i32();
    int32_t main_children = main.i32();
    size_t p = 20 + size_t(main_content);
    size_t end = std::min(b.size(), p + size_t(main_children));
    std::vector<Model> models;
    std::map<int, Node> nodes;
    std::map<int, bool> layer_hidden;
    while (p + 12 <= end) {
        std::memcpy(id, &b[p], 4);
        Reader h{b, p + 4, end};
        int32_t content = h.i32(), children = h.i32();
        size_t cstart = p + 12, cend = cstart + size_t(content);
        if (content < 0 || children < 0 || cend > end) fail("bad chunk size");
        Reader r{b, cstart, cend};
        std::string kind(id);
        if (kind == "SIZE") {
            Model m;
            m.sx = r.i32();
            m.sy = r.i32();
            m.sz = r.i32();
            models.push_back(m);
        } else if (kind == "XYZI") {
            if (models.empty()) fail("XYZI before SIZE");
            int32_t n = r.i32();
            if (n < 0 || r.pos + size_t(n) * 4 > cend) fail("bad XYZI");
            for (int32_t k = 0; k < n; ++k) {
                const uint8_t* v = &b[r.pos + size_t(k) * 4];
                models.back().voxels.push_back({int(v[0]), int(v[1]), int(v[2])});
            }
        } else if (kind == "nTRN") {
            int nid = r.i32();
            Node n;
            n.kind = Node::Transform;
            n.attrs = r.dict();
            n.child = r.i32();
            r.i32();  // reserved
            n.layer = r.i32();
            int frames = r.i32();
            for (int f = 0; f < frames; ++f) {
                auto d = r.dict();
                if (f == 0) n.frame0 = d;
            }
            nodes[nid] = n;
        } else if (kind == "nGRP") {
            int nid = r.i32();
            Node n;
            n.kind = Node::Group;
            n.attrs = r.dict();
            int k = r.i32();
            for (int c = 0; c < k; ++c) n.children.push_back(r.i32());
            nodes[nid] = n;
        } else if (kind == "nSHP") {
            int nid = r.i32();
            Node n;
            n.kind = Node::Shape;
            n.attrs = r.dict();
            int k = r.i32();
            for (int c = 0; c < k; ++c) {
                int m = r.i32();
                r.dict();
                if (c == 0) n.model = m;
            }
            nodes[nid] = n;
        } else if (kind == "LAYR") {
            int lid = r.i32();
            layer_hidden[lid] = hidden(r.dict());
        }
        p = cend + size_t(children);
    }
    // Placements: (model, transform), depth first from node 0 in child order.
    std::vector<std::pair<int, Affine>> placed;
    if (nodes.empty()) {
        for (size_t m = 0; m < models.size(); ++m) placed.push_back({int(m), Affine()});
    } else {
        std::vector<std::pair<int, Affine>> stack{{0, Affine()}};
        std::set<int> seen;
        while (!stack.empty()) {
            auto [id0, parent] = stack.back();
            stack.pop_back();
            auto it = nodes.find(id0);
            if (it == nodes.end()) fail("dangling node " + std::to_string(id0));
            if (!seen.insert(id0).second) fail("node used twice");
            const Node& n = it->second;
            if (hidden(n.attrs)) continue;
            if (n.kind == Node::Transform) {
                if (layer_hidden.count(n.layer) && layer_hidden[n.layer]) continue;
                stack.push_back({n.child, parent.then(frame_affine(n.frame0))});
            } else if (n.kind == Node::Group) {
                for (auto c = n.children.rbegin(); c != n.children.rend(); ++c)
                    stack.push_back({*c, parent});
            } else if (n.model >= 0) {
                if (size_t(n.model) >= models.size()) fail("shape uses a missing model");
                placed.push_back({n.model, parent});
            }
        }
    }
    // Voxel v of a model of size s goes to t + floor(R (v + 1/2 - floor(s/2))), in doubled
    // integers: 2v + 1 - 2 floor(s/2) is odd, so R of it halves to a floor exactly.
    std::vector<std::array<long, 3>> out;
    for (auto& [m, a] : placed) {
        const Model& md = models[size_t(m)];
        long piv[3] = {2L * (md.sx / 2), 2L * (md.sy / 2), 2L * (md.sz / 2)};
        for (auto& v : md.voxels) {
            long d[3] = {2L * v[0] + 1 - piv[0], 2L * v[1] + 1 - piv[1], 2L * v[2] + 1 - piv[2]};
            std::array<long, 3> w;
            for (int i = 0; i < 3; ++i)
                w[i] = floor_div2(a.r[i][0] * d[0] + a.r[i][1] * d[1] + a.r[i][2] * d[2]) + a.t[i];
            out.push_back(w);
        }
    }
    return out;
}

// ---------------------------------------------------------------- camera

struct V3 {
    double x, y, z;
};
V3 add(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
V3 sub(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V3 mul(V3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
V3 cross(V3 a, V3 b) {
    return {a.y * b.z - b.y * a.z, a.z * b.x - b.z * a.x, a.x * b.y - b.x * a.y};
}
V3 normalise(V3 a) {
    double len = std::sqrt((a.x * a.x + a.y * a.y) + a.z * a.z);
    return mul(a, 1.0 / len);
}

struct Camera {
    V3 eye, forward, right, up;
    bool ortho;
    double tau, view_width;
    int w, h;
    void ray(int i, int j, V3& o, V3& d) const {
        double W = w, H = h;
        if (!ortho) {
            double aspect = W / H;
            double u = (2.0 * (double(i) + 0.5) / W - 1.0) * tau * aspect;
            double v = (1.0 - 2.0 * (double(j) + 0.5) / H) * tau;
            o = eye;
            d = normalise(add(add(forward, mul(right, u)), mul(up, v)));
        } else {
            double hw = view_width * 0.5;
            double hh = hw * H / W;
            double u = (2.0 * (double(i) + 0.5) / W - 1.0) * hw;
            double v = (1.0 - 2.0 * (double(j) + 0.5) / H) * hh;
            o = add(add(eye, mul(right, u)), mul(up, v));
            d = forward;
        }
        d = {d.x + 0.0, d.y + 0.0, d.z + 0.0};
    }
};

// ---------------------------------------------------------------- tracing

using GridT = openvdb::BoolGrid;
using RayT = openvdb::math::Ray<double>;
using Intersector = openvdb::tools::VolumeRayIntersector<GridT>;

struct Hit {
    V3 o, d;
    bool hit;
    double t;
    openvdb::Coord voxel;
};

// The accessor OpenVDB documents for a read-only walk on one thread: not registered with the
// tree (a registered accessor is inserted into the tree's concurrent accessor registry when it
// is made and erased when it dies, so that the tree can clear its caches on a change; this
// tree does not change while it is traced).
using AccessorT = GridT::ConstUnsafeAccessor;

Hit trace(Intersector& inter, AccessorT& acc, const Camera& cam, int i, int j) {
    Hit r;
    cam.ray(i, j, r.o, r.d);
    r.hit = false;
    r.t = -1.0;
    RayT ray(openvdb::Vec3d(r.o.x, r.o.y, r.o.z), openvdb::Vec3d(r.d.x, r.d.y, r.d.z), 0.0,
             std::numeric_limits<double>::max());
    if (!inter.setIndexRay(ray)) return r;
    double t0, t1;
    while (inter.march(t0, t1)) {
        openvdb::math::DDA<RayT, 0> dda(ray, t0, t1);
        do {
            if (acc.isValueOn(dda.voxel())) {
                r.hit = true;
                r.t = std::max(dda.time(), 0.0);
                r.voxel = dda.voxel();
                return r;
            }
        } while (dda.step());
    }
    return r;
}

// Worker threads made once, before any timed render: each keeps its own shallow copy of the
// intersector (OpenVDB's documented pattern: the copy shares the master's tree and has its own
// accessor) and its own accessor, and renders rows th, th + n, ... each time it is released.
class Pool {
public:
    Pool(int n, const Intersector& master, const GridT& grid, const Camera& cam,
         std::vector<Hit>& hits)
        : n_(n) {
        for (int th = 0; th < n; ++th)
            threads_.emplace_back([this, th, &master, &grid, &cam, &hits] {
                Intersector inter(master);
                AccessorT acc = grid.getConstUnsafeAccessor();
                unsigned seen = 0;
                for (;;) {
                    {
                        std::unique_lock<std::mutex> l(m_);
                        go_.wait(l, [&] { return generation_ != seen || quit_; });
                        if (quit_) return;
                        seen = generation_;
                    }
                    for (int j = th; j < cam.h; j += n_)
                        for (int i = 0; i < cam.w; ++i)
                            hits[size_t(j) * size_t(cam.w) + size_t(i)] = trace(inter, acc, cam, i, j);
                    {
                        std::lock_guard<std::mutex> l(m_);
                        ++done_;
                    }
                    finished_.notify_one();
                }
            });
    }
    ~Pool() {
        {
            std::lock_guard<std::mutex> l(m_);
            quit_ = true;
        }
        go_.notify_all();
        for (auto& t : threads_) t.join();
    }
    // One render of every pixel on all threads; returns its wall time in seconds.
    double render() {
        auto start = std::chrono::steady_clock::now();
        {
            std::lock_guard<std::mutex> l(m_);
            done_ = 0;
            ++generation_;
        }
        go_.notify_all();
        std::unique_lock<std::mutex> l(m_);
        finished_.wait(l, [&] { return done_ == n_; });
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }

private:
    int n_;
    std::vector<std::thread> threads_;
    std::mutex m_;
    std::condition_variable go_, finished_;
    unsigned generation_ = 0;
    int done_ = 0;
    bool quit_ = false;
};

void put(std::vector<uint8_t>& out, const void* p, size_t n) {
    const uint8_t* c = static_cast<const uint8_t*>(p);
    out.insert(out.end(), c, c + n);
}

}  // namespace

int main(int argc, char** argv) {
    try {
        if (argc < 16) {
            std::fprintf(stderr,
                         "usage: peer MODEL.vox OUT.bin W H ex ey ez lx ly lz ux uy uz "
                         "(pinhole FOV | ortho WIDTH) [THREADS [REPEAT]]\n");
            return 2;
        }
        openvdb::initialize();
        std::string model = argv[1], out_path = argv[2];
        Camera cam;
        cam.w = std::atoi(argv[3]);
        cam.h = std::atoi(argv[4]);
        double a[9];
        for (int k = 0; k < 9; ++k) a[k] = std::strtod(argv[5 + k], nullptr);
        std::string proj = argv[14];
        double pv = std::strtod(argv[15], nullptr);
        int threads = argc > 16 ? std::atoi(argv[16]) : 1;
        int repeat = argc > 17 ? std::atoi(argv[17]) : 1;
        if (cam.w <= 0 || cam.h <= 0 || threads <= 0 || repeat <= 0) fail("bad size/threads");
        V3 eye{a[0], a[1], a[2]}, look{a[3], a[4], a[5]}, up{a[6], a[7], a[8]};
        cam.eye = eye;
        cam.forward = normalise(sub(look, eye));
        cam.right = normalise(cross(cam.forward, up));
        cam.up = cross(cam.right, cam.forward);
        cam.ortho = proj == "ortho";
        constexpr double kRadPerDeg = M_PI / 180.0;
        cam.tau = cam.ortho ? 0.0 : std::tan(pv * kRadPerDeg * 0.5);
        cam.view_width = pv;

        auto placed = read_vox(model);
        if (placed.empty()) fail("no visible voxels");
        std::unordered_set<openvdb::Coord> solid;  // openvdb::Coord has std::hash
        for (auto& w : placed) solid.insert(openvdb::Coord(int(w[0]), int(w[1]), int(w[2])));
        GridT::Ptr grid = GridT::create(false);
        auto wacc = grid->getAccessor();
        openvdb::Coord lo(INT32_MAX), hi(INT32_MIN);
        size_t surface = 0;
        const int nb[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
        for (auto& c : solid) {
            lo.minComponent(c);
            hi.maxComponent(c);
            bool open = false;
            for (auto& n : nb)
                open = open || !solid.count(c.offsetBy(n[0], n[1], n[2]));
            if (open) {
                wacc.setValueOn(c, true);
                ++surface;
            }
        }
        Intersector master(*grid);
        std::vector<Hit> hits(size_t(cam.w) * size_t(cam.h));
        std::vector<double> times;
        {
            Pool pool(threads, master, *grid, cam, hits);
            // One untimed render first: it faults in the hit records and warms the caches.
            pool.render();
            for (int rep = 0; rep < repeat; ++rep) times.push_back(pool.render());
        }
        std::sort(times.begin(), times.end());
        double best = times.front();
        double median = times.size() % 2 ? times[times.size() / 2]
                                         : 0.5 * (times[times.size() / 2 - 1] + times[times.size() / 2]);
        std::vector<uint8_t> out;
        out.insert(out.end(), {'S', 'V', 'O', 'M', 'H', 'I', 'T', '1'});
        uint32_t header[6] = {1, uint32_t(cam.w), uint32_t(cam.h), 80, cam.ortho ? 1u : 0u, 0};
        put(out, header, sizeof header);
        for (size_t k = 0; k < hits.size(); ++k) {
            const Hit& r = hits[k];
            double f[7] = {r.o.x, r.o.y, r.o.z, r.d.x, r.d.y, r.d.z, r.t};
            put(out, f, sizeof f);
            int32_t v[3] = {0, 0, 0};
            if (r.hit) v[0] = r.voxel.x(), v[1] = r.voxel.y(), v[2] = r.voxel.z();
            put(out, v, sizeof v);
            uint8_t flags[8] = {uint8_t(r.hit), 0, 0, 0, 0, 0, 0, 0};
            put(out, flags, sizeof flags);
            uint16_t px[2] = {uint16_t(k % size_t(cam.w)), uint16_t(k / size_t(cam.w))};
            put(out, px, sizeof px);
        }
        std::ofstream f(out_path, std::ios::binary);
        f.write(reinterpret_cast<const char*>(out.data()), std::streamsize(out.size()));
        if (!f) fail("cannot write " + out_path);
        std::printf("solid_min %d %d %d\nsolid_max %d %d %d\nvoxels %zu\nsurface %zu\ntrace_seconds %.9f\n"
                    "trace_median_seconds %.9f\n",
                    lo.x(), lo.y(), lo.z(), hi.x(), hi.y(), hi.z(), solid.size(), surface, best,
                    median);
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "peer: %s\n", e.what());
        return 1;
    }
}

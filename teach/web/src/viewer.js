// The viewer of `octrace explain --html`: the model, the octree cells one ray's traversal
// touched (coloured by visit order), the ray, its hit and its shadow ray, with orbit controls
// and the list of steps; hovering or clicking a step highlights the cell or the primitive it
// names, and the step controls (buttons, arrow keys, play) walk through them with the camera
// framing the current cell. Everything starts from the JSON in <script id="octrace-data">
// (teach/explain_page.cpp writes it); esbuild bundles this file with three.js into the one
// script the page inlines.
//
// The page's kernel (OctracePageKernel, octrace's kernel compiled to WebAssembly, in the script
// before this one) rebuilds the layout from the scene in that JSON, renders the image shown in
// the panel, and explains any pixel clicked with the same code as `octrace explain`. Without it
// (a build without emscripten, or a --ray page) the page shows the recorded pixel and says so.
//
// For tests (tests/teach/browser_test.cpp) the page reports its state in the DOM:
// <body data-octrace="rendered"> once the first frame is drawn, "error" when anything threw;
// data-kernel="ready" (or "absent", "failed") once the kernel has loaded; with #test=X,Y;X,Y
// in the address, each pixel is explained in turn and <pre id="octrace-test"> receives one
// JSON line per pixel ({x, y, ms, kernel_ms, json, svg}: json is the kernel's explain --json
// text, svg its 2D view), then
// data-test="done".
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

function decodeBase64(text, Type) {
    const bytes = Uint8Array.from(atob(text), (c) => c.charCodeAt(0));
    return new Type(bytes.buffer);
}

function boxEdges(box, colour, opacity) {
    const [x0, y0, z0, x1, y1, z1] = box;
    const geom = new THREE.EdgesGeometry(new THREE.BoxGeometry(x1 - x0, y1 - y0, z1 - z0));
    const mat = new THREE.LineBasicMaterial({
        color: colour,
        transparent: opacity < 1,
        opacity,
    });
    const lines = new THREE.LineSegments(geom, mat);
    lines.position.set((x0 + x1) / 2, (y0 + y1) / 2, (z0 + z1) / 2);
    return lines;
}

// A segment drawn as a thin cylinder (WebGL lines are one pixel wide whatever is asked).
function rod(from, to, radius, colour) {
    const a = new THREE.Vector3(...from);
    const b = new THREE.Vector3(...to);
    const length = a.distanceTo(b);
    const geom = new THREE.CylinderGeometry(radius, radius, Math.max(length, 1e-9), 10, 1);
    const mesh = new THREE.Mesh(geom, new THREE.MeshBasicMaterial({ color: colour }));
    mesh.position.copy(a).add(b).multiplyScalar(0.5);
    mesh.quaternion.setFromUnitVectors(
        new THREE.Vector3(0, 1, 0),
        b.clone().sub(a).normalize(),
    );
    return mesh;
}

function ball(at, radius, colour) {
    const mesh = new THREE.Mesh(
        new THREE.SphereGeometry(radius, 16, 12),
        new THREE.MeshBasicMaterial({ color: colour }),
    );
    mesh.position.set(...at);
    return mesh;
}

// The model's arrays as bytes, decoded once: the viewer draws them, and the kernel rebuilds the
// scene's triangles from them (when the model is not decimated).
function modelBytes(data) {
    if (!data.modelBytes) {
        const m = data.mesh;
        data.modelBytes = {
            positions: decodeBase64(m.positions, Uint8Array),
            indices: m.indices ? decodeBase64(m.indices, Uint8Array) : null,
        };
    }
    return data.modelBytes;
}

function buildModel(data, scene) {
    const m = data.mesh;
    const bytes = modelBytes(data);
    const geom = new THREE.BufferGeometry();
    const positions = new Float32Array(bytes.positions.buffer);
    geom.setAttribute('position', new THREE.BufferAttribute(positions, 3));
    let object;
    if (m.kind === 'triangles') {
        geom.setIndex(new THREE.BufferAttribute(new Uint32Array(bytes.indices.buffer), 1));
        geom.computeVertexNormals();
        object = new THREE.Mesh(
            geom,
            new THREE.MeshLambertMaterial({
                color: 0xd9ccb3,
                side: THREE.DoubleSide,
                transparent: true,
                opacity: 0.55,
                depthWrite: false,
            }),
        );
    } else {
        object = new THREE.Points(
            geom,
            new THREE.PointsMaterial({ color: 0xd9ccb3, size: 2 * m.radius, sizeAttenuation: true }),
        );
    }
    scene.add(object);
    return object;
}

// Line segments of many boxes in one geometry (the depth slider can show thousands of cells).
function boxesGeometry(boxes) {
    const corners = (b) => [
        [b[0], b[1], b[2]], [b[3], b[1], b[2]], [b[3], b[4], b[2]], [b[0], b[4], b[2]],
        [b[0], b[1], b[5]], [b[3], b[1], b[5]], [b[3], b[4], b[5]], [b[0], b[4], b[5]],
    ];
    const edges = [[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4],
        [0, 4], [1, 5], [2, 6], [3, 7]];
    const pos = new Float32Array(boxes.length * 12 * 6);
    let i = 0;
    for (const b of boxes) {
        const c = corners(b);
        for (const [p, q] of edges) {
            pos.set(c[p], i);
            pos.set(c[q], i + 3);
            i += 6;
        }
    }
    const geom = new THREE.BufferGeometry();
    geom.setAttribute('position', new THREE.BufferAttribute(pos, 3));
    return geom;
}

// The kernel: OctracePageKernel() resolves to the emscripten module; its C functions are
// called through ccall with JSON strings in and out (teach/wasm/page_kernel.cpp).
async function loadKernel(data) {
    if (!data.kernel) return { absent: data.kernel_missing || 'no kernel in this page' };
    if (typeof OctracePageKernel !== 'function')
        return { absent: 'the page kernel script is missing' };
    const module = await OctracePageKernel();
    const call = (name, types, args) =>
        JSON.parse(module.ccall(name, 'string', types, args));
    // The primitives go in as bytes in the module's heap (a string argument would be copied
    // onto its 5 MB stack): the model mesh's, or the spec's own base64 data.
    const spec = { ...data.kernel, scene: { ...data.kernel.scene, data: null } };
    const blobs = data.kernel.scene.from_model
        ? [modelBytes(data).positions, modelBytes(data).indices]
        : [decodeBase64(data.kernel.scene.data, Uint8Array), null];
    const ptrs = blobs.map((b) => {
        if (!b) return 0;
        const p = module._malloc(Math.max(1, b.length));
        module.HEAPU8.set(b, p);
        return p;
    });
    const loaded = call('octPageLoad', ['string', 'number', 'number', 'number', 'number'], [
        JSON.stringify(spec), ptrs[0], blobs[0].length, ptrs[1], blobs[1] ? blobs[1].length : 0,
    ]);
    ptrs.forEach((p) => p && module._free(p));
    if (loaded.error) return { failed: loaded.error };
    return {
        loaded,
        explain(x, y) {
            const page = call('octPageExplain', ['number', 'number'], [x, y]);
            if (page.error) throw new Error(page.error);
            page.json = module.ccall('octPageExplanation', 'string', [], []);
            return page;
        },
        pixel: (x, y) => call('octPagePixel', ['number', 'number'], [x, y]),
        cells: (depth) => call('octPageCells', ['number'], [depth]).cells,
        image(cost) {
            const ptr = module.ccall('octPageImage', 'number', ['number'], [cost ? 1 : 0]);
            const n = loaded.width * loaded.height * 4;
            return new Uint8ClampedArray(module.HEAPU8.buffer, ptr, n).slice();
        },
    };
}

function main(data, kernel) {
    const view = document.getElementById('view');
    const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    renderer.setPixelRatio(window.devicePixelRatio || 1);
    renderer.setSize(view.clientWidth, view.clientHeight);
    renderer.setClearColor(0x15171f);
    view.appendChild(renderer.domElement);

    const scene = new THREE.Scene();
    scene.add(new THREE.AmbientLight(0xffffff, 0.9));
    const sun = new THREE.DirectionalLight(0xffffff, 1.6);
    sun.position.set(...data.light);
    scene.add(sun);

    const [lo, hi] = [data.root.slice(0, 3), data.root.slice(3, 6)];
    const diag = new THREE.Vector3(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]).length();
    const model = buildModel(data, scene);
    scene.add(boxEdges(data.root, 0x5a6070, 0.6));
    scene.add(ball(data.light, diag * 0.0075, 0xffe14d));

    const camera = new THREE.PerspectiveCamera(
        45,
        view.clientWidth / view.clientHeight,
        diag * 1e-4,
        diag * 100,
    );
    const controls = new OrbitControls(camera, renderer.domElement);
    function render() {
        renderer.render(scene, camera);
    }
    controls.addEventListener('change', render);
    window.addEventListener('resize', () => {
        camera.aspect = view.clientWidth / view.clientHeight;
        camera.updateProjectionMatrix();
        renderer.setSize(view.clientWidth, view.clientHeight);
        render();
    });

    // What belongs to the explained pixel: rebuilt by showPixel for each pixel explained.
    const pixelGroup = new THREE.Group();
    const missedGroup = new THREE.Group();
    const primGroup = new THREE.Group();
    const highlight = new THREE.Group();
    missedGroup.visible = false;
    scene.add(pixelGroup, missedGroup, primGroup, highlight);
    const treeGroup = new THREE.Group();
    scene.add(treeGroup);

    let page = null;
    let cellObjects = new Map();
    let primById = new Map();
    let items = [];
    let cursor = -1;  // the current step line (index into page.lines), -1: none
    let playing = null;
    const list = document.getElementById('steps');
    const follow = document.getElementById('follow');

    function clearGroup(g) {
        for (const child of [...g.children]) {
            g.remove(child);
            child.traverse?.((o) => o.geometry?.dispose());
        }
    }

    function cellOf(line) {
        return line && line.key ? cellObjects.get(line.ray + ':' + line.key) : null;
    }

    function show(line) {
        highlight.clear();
        if (!line) return;
        const c = cellOf(line);
        if (c) {
            const [x0, y0, z0, x1, y1, z1] = c.box;
            const fill = new THREE.Mesh(
                new THREE.BoxGeometry(x1 - x0, y1 - y0, z1 - z0),
                new THREE.MeshBasicMaterial({
                    color: 0xffe14d,
                    transparent: true,
                    opacity: 0.25,
                    depthWrite: false,
                }),
            );
            fill.position.set((x0 + x1) / 2, (y0 + y1) / 2, (z0 + z1) / 2);
            highlight.add(fill);
            highlight.add(boxEdges(c.box, 0xffe14d, 1));
        }
        if (line.prim >= 0) {
            const p = primById.get(line.prim);
            if (p && p.v) {
                const g = new THREE.BufferGeometry();
                g.setAttribute('position', new THREE.BufferAttribute(new Float32Array(p.v), 3));
                highlight.add(
                    new THREE.Mesh(
                        g,
                        new THREE.MeshBasicMaterial({ color: 0xffe14d, side: THREE.DoubleSide }),
                    ),
                );
            } else if (p && p.c) {
                highlight.add(ball(p.c, p.r * 1.05, 0xffe14d));
            }
        }
    }

    // The camera frames the current step's cell (or primitive): same direction of view, the
    // target at its centre, far enough to see it whole and its neighbours.
    function frame(line) {
        let box = cellOf(line)?.box;
        const p = line && line.prim >= 0 ? primById.get(line.prim) : null;
        if (!box && p && p.v) {
            const v = p.v;
            box = [Math.min(v[0], v[3], v[6]), Math.min(v[1], v[4], v[7]),
                Math.min(v[2], v[5], v[8]), Math.max(v[0], v[3], v[6]),
                Math.max(v[1], v[4], v[7]), Math.max(v[2], v[5], v[8])];
        } else if (!box && p && p.c) {
            box = [p.c[0] - p.r, p.c[1] - p.r, p.c[2] - p.r, p.c[0] + p.r, p.c[1] + p.r,
                p.c[2] + p.r];
        }
        if (!box) return;
        const centre = new THREE.Vector3((box[0] + box[3]) / 2, (box[1] + box[4]) / 2,
            (box[2] + box[5]) / 2);
        // No closer than 3 % of the scene: the rays are drawn as rods of 0.25 % of it.
        const size = Math.max(box[3] - box[0], box[4] - box[1], box[5] - box[2], diag * 0.03);
        const dir = camera.position.clone().sub(controls.target).normalize();
        controls.target.copy(centre);
        camera.position.copy(centre).add(dir.multiplyScalar(size * 3.2));
        controls.update();
    }

    function setCursor(i) {
        const was = list.querySelector('li.pinned');
        if (was) was.classList.remove('pinned');
        cursor = i;
        if (cursor >= 0 && items[cursor]) {
            items[cursor].classList.add('pinned');
            items[cursor].scrollIntoView({ block: 'nearest' });
            const l = page.lines[cursor];
            const where = page.pixel && kernel.explain ? 'pixel=' + page.pixel.join(',') + '&' : '';
            history.replaceState(null, '', '#' + where + (l.ray ? 'shadow' : 'step') + '=' + l.step);
            show(l);
            if (follow.checked) frame(l);
        } else {
            show(null);
        }
        render();
    }

    // The step lines that can be stepped to, in order.
    function stepLines() {
        return page.lines.map((l, i) => (l.heading ? -1 : i)).filter((i) => i >= 0);
    }
    function step(delta) {
        const s = stepLines();
        if (!s.length) return;
        const at = s.indexOf(cursor);
        const next = at < 0 ? (delta > 0 ? 0 : s.length - 1)
            : Math.min(s.length - 1, Math.max(0, at + delta));
        setCursor(s[next]);
        return next < s.length - 1;
    }
    function stop() {
        if (playing) clearInterval(playing);
        playing = null;
        document.getElementById('play').textContent = '\u25B6';
    }
    function play() {
        if (playing) return stop();
        document.getElementById('play').textContent = '\u23F8';
        const rate = Number(document.getElementById('speed').value);
        playing = setInterval(() => {
            if (!step(1)) stop();
        }, 1000 / rate);
    }

    function showPixel(d) {
        stop();
        page = d;
        clearGroup(pixelGroup);
        clearGroup(missedGroup);
        clearGroup(primGroup);
        highlight.clear();
        cellObjects = new Map();
        for (const c of d.cells) {
            const obj = boxEdges(c.box, c.visited ? c.colour : 0x8a8f99, c.visited ? 1 : 0.35);
            (c.visited ? pixelGroup : missedGroup).add(obj);
            cellObjects.set(c.ray + ':' + c.key, c);
        }
        const rodRadius = diag * 0.0025;
        for (const r of d.rays) {
            pixelGroup.add(rod(r.from, r.to, rodRadius, r.colour));
            if (r.hit) pixelGroup.add(ball(r.hit, rodRadius * 3, r.colour));
        }
        // The primitives the rays tested: hit ones red, the others blue.
        primById = new Map(d.prims.map((p) => [p.id, p]));
        const unitSphere = new THREE.SphereGeometry(1, 16, 12);
        for (const p of d.prims) {
            const material = new THREE.MeshBasicMaterial({
                color: p.hit ? 0xff3b30 : 0x4da3ff,
                side: THREE.DoubleSide,
                transparent: true,
                opacity: p.hit ? 0.95 : 0.6,
            });
            let mesh;
            if (p.v) {
                const g = new THREE.BufferGeometry();
                g.setAttribute('position', new THREE.BufferAttribute(new Float32Array(p.v), 3));
                mesh = new THREE.Mesh(g, material);
            } else {
                mesh = new THREE.Mesh(unitSphere, material);
                mesh.position.set(...p.c);
                mesh.scale.setScalar(p.r);
            }
            primGroup.add(mesh);
        }
        camera.position.set(...d.view.eye);
        camera.up.set(...d.view.up);
        controls.target.set(...d.view.target);
        controls.update();

        const plane = document.getElementById('plane-view');
        plane.innerHTML = d.svg || '';
        if (!d.svg) plane.textContent = '2D view: ' + (d.svg_error || 'none');
        document.getElementById('title').textContent = d.title;
        document.title = d.title;
        document.getElementById('summary').textContent = d.summary;
        document.getElementById('note').textContent =
            [data.model_note, d.prims_note].filter((t) => t).join(' ');

        list.textContent = '';
        items = [];
        cursor = -1;
        d.lines.forEach((line, i) => {
            const li = document.createElement('li');
            li.textContent = line.text;
            if (line.heading) {
                li.className = 'heading';
                list.appendChild(li);
                return;
            }
            li.className = 'step' + (line.key || line.prim >= 0 ? ' names' : '');
            li.dataset.index = String(i);
            li.addEventListener('mouseenter', () => {
                show(line);
                render();
            });
            li.addEventListener('mouseleave', () => {
                show(cursor >= 0 ? page.lines[cursor] : null);
                render();
            });
            li.addEventListener('click', () => {
                stop();
                if (cursor === i) {
                    setCursor(-1);
                    history.replaceState(null, '', location.pathname + location.search);
                } else {
                    setCursor(i);
                }
            });
            items[i] = li;
            list.appendChild(li);
        });
        render();
    }

    // The line covering step N of a ray: the last one starting at or before it.
    function lineOfStep(ray, n) {
        let found = -1;
        page.lines.forEach((l, i) => {
            if (!l.heading && l.ray === ray && l.step <= n) found = i;
        });
        return found;
    }

    // --- the image and the kernel ------------------------------------------------------------
    const state = document.getElementById('kernel-state');
    const canvas = document.getElementById('image');
    const costBox = document.getElementById('show-cost');
    const info = document.getElementById('pixel-info');
    function drawImage() {
        if (!kernel.loaded) return;
        const { width, height } = kernel.loaded;
        const img = new ImageData(kernel.image(costBox.checked), width, height);
        canvas.getContext('2d').putImageData(img, 0, 0);
        document.getElementById('cost-scale').textContent = costBox.checked
            ? 'inferno: 0 to ' + kernel.loaded.cost_scale + ' boxes tested (99th percentile)'
            : '';
    }
    function explainAt(x, y) {
        const d = kernel.explain(x, y);
        showPixel(d);
        const c = kernel.pixel(x, y);
        info.textContent = 'pixel (' + x + ', ' + y + '): ' + c.boxes + ' boxes tested, ' +
            c.prims + ' primitives tested; explained in ' + d.ms.toFixed(1) + ' ms';
        return d;
    }
    if (kernel.loaded) {
        const { width, height } = kernel.loaded;
        canvas.width = width;
        canvas.height = height;
        drawImage();
        state.textContent = 'This page traces rays itself: octrace\u2019s kernel in WebAssembly ' +
            'rebuilt the ' + data.kernel.layout + ' layout (' + kernel.loaded.nodes +
            ' nodes, identical to octrace\u2019s: fingerprint ' + kernel.loaded.fingerprint +
            ') in ' + kernel.loaded.build_ms.toFixed(0) + ' ms and rendered the image in ' +
            kernel.loaded.render_ms.toFixed(0) + ' ms.';
        canvas.addEventListener('click', (ev) => {
            const r = canvas.getBoundingClientRect();
            const x = Math.floor(((ev.clientX - r.left) / r.width) * width);
            const y = Math.floor(((ev.clientY - r.top) / r.height) * height);
            if (x < 0 || y < 0 || x >= width || y >= height) return;
            explainAt(x, y);
            history.replaceState(null, '', '#pixel=' + x + ',' + y);
        });
        costBox.addEventListener('change', drawImage);
        // The depth slider: every cell of the tree at that depth, faint (leaves brighter).
        const depth = document.getElementById('depth');
        depth.max = String(kernel.loaded.max_depth);
        depth.addEventListener('input', () => {
            clearGroup(treeGroup);
            const d = Number(depth.value);
            document.getElementById('depth-value').textContent = d < 0 ? 'off' : String(d);
            if (d >= 0) {
                const cells = kernel.cells(d);
                const leaves = cells.filter((c) => c[6] === 1);
                const others = cells.filter((c) => c[6] !== 1);
                treeGroup.add(new THREE.LineSegments(boxesGeometry(others),
                    new THREE.LineBasicMaterial({ color: 0x6f7585, transparent: true,
                        opacity: 0.35 })));
                treeGroup.add(new THREE.LineSegments(boxesGeometry(leaves),
                    new THREE.LineBasicMaterial({ color: 0x9fd3ff, transparent: true,
                        opacity: 0.6 })));
                document.getElementById('depth-value').textContent = d + ' (' + cells.length +
                    ' cells, ' + leaves.length + ' leaves with primitives)';
            }
            render();
        });
    } else {
        document.getElementById('image-box').style.display = 'none';
        document.getElementById('depth').disabled = true;
        state.textContent = 'This page shows the pixel octrace recorded, and cannot explain ' +
            'others: ' + (kernel.absent || 'its kernel failed: ' + kernel.failed);
        if (kernel.failed) console.error('page kernel: ' + kernel.failed);
    }

    // --- controls ----------------------------------------------------------------------------
    document.getElementById('first').addEventListener('click', () => {
        stop();
        setCursor(stepLines()[0] ?? -1);
    });
    document.getElementById('prev').addEventListener('click', () => {
        stop();
        step(-1);
    });
    document.getElementById('next').addEventListener('click', () => {
        stop();
        step(1);
    });
    document.getElementById('play').addEventListener('click', play);
    window.addEventListener('keydown', (ev) => {
        if (ev.target.tagName === 'INPUT' || ev.target.tagName === 'SELECT') return;
        if (ev.key === 'ArrowRight' || ev.key === 'ArrowDown') step(1);
        else if (ev.key === 'ArrowLeft' || ev.key === 'ArrowUp') step(-1);
        else if (ev.key === ' ') play();
        else if (ev.key === 'Home') setCursor(stepLines()[0] ?? -1);
        else return;
        ev.preventDefault();
    });
    document.getElementById('show-missed').addEventListener('change', (ev) => {
        missedGroup.visible = ev.target.checked;
        render();
    });
    // The 2D view (`octrace explain --svg`'s figure of the same pixel) over the 3D one.
    document.getElementById('show-plane').addEventListener('change', (ev) => {
        document.getElementById('plane-view').style.display = ev.target.checked ? 'block' : 'none';
    });
    document.getElementById('show-model').addEventListener('change', (ev) => {
        model.visible = ev.target.checked;
        render();
    });

    // The address: #pixel=X,Y explains that pixel (with the kernel), #step=N / #shadow=N pins
    // a step of it.
    const hash = new URLSearchParams(location.hash.slice(1));
    const wanted = hash.get('pixel')?.split(',').map(Number);
    if (kernel.loaded && wanted && wanted.length === 2) explainAt(wanted[0], wanted[1]);
    else showPixel(data);
    for (const [name, ray] of [['step', 0], ['shadow', 1]]) {
        if (!hash.has(name)) continue;
        const found = lineOfStep(ray, Number(hash.get(name)));
        if (found >= 0) setCursor(found);
    }
    render();
    if (document.body.dataset.octrace !== 'error') document.body.dataset.octrace = 'rendered';

    // Tests: #test=X,Y;X,Y explains each pixel and writes the kernel's JSON into the page.
    const test = hash.get('test');
    if (test !== null && kernel.loaded) {
        const out = document.createElement('pre');
        out.id = 'octrace-test';
        document.body.appendChild(out);
        for (const pair of test.split(';')) {
            const [x, y] = pair.split(',').map(Number);
            const t0 = performance.now();
            const d = explainAt(x, y);
            const ms = performance.now() - t0;
            out.textContent +=
                JSON.stringify({ x, y, ms, kernel_ms: d.ms, json: d.json, svg: d.svg }) + '\n';
        }
    }
    document.body.dataset.test = 'done';
}

async function start() {
    const data = JSON.parse(document.getElementById('octrace-data').textContent);
    let kernel;
    try {
        kernel = await loadKernel(data);
    } catch (err) {
        kernel = { failed: String(err && err.message ? err.message : err) };
    }
    document.body.dataset.kernel = kernel.loaded ? 'ready' : kernel.absent ? 'absent' : 'failed';
    main(data, kernel);
}

start();

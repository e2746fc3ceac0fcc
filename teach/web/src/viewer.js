// The viewer of `octrace explain --html`: the model, the octree cells one ray's traversal
// touched (coloured by visit order), the ray, its hit and its shadow ray, with orbit controls
// and the list of steps; hovering or clicking a step highlights the cell or the primitive it
// names. Everything comes from the JSON in <script id="octrace-data"> (teach/explain_page.cpp
// writes it); esbuild bundles this file with three.js into the one script the page inlines.
//
// For tests (tests/teach/browser_test.cpp) the page reports its state in the DOM:
// <body data-octrace="rendered"> once the first frame is drawn, "error" when anything threw.
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

function buildModel(data, scene) {
    const m = data.mesh;
    const positions = decodeBase64(m.positions, Float32Array);
    const geom = new THREE.BufferGeometry();
    geom.setAttribute('position', new THREE.BufferAttribute(positions, 3));
    let object;
    if (m.kind === 'triangles') {
        geom.setIndex(new THREE.BufferAttribute(decodeBase64(m.indices, Uint32Array), 1));
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

function main() {
    const data = JSON.parse(document.getElementById('octrace-data').textContent);
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
    const centre = new THREE.Vector3((lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2);
    const diag = new THREE.Vector3(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]).length();

    const model = buildModel(data, scene);
    scene.add(boxEdges(data.root, 0x5a6070, 0.6));

    // Cells: visited ones in their visit-order colour, the others (boxes tested and missed,
    // nodes dropped) faint grey behind a checkbox.
    const cellObjects = new Map();
    const missedGroup = new THREE.Group();
    for (const c of data.cells) {
        const obj = boxEdges(c.box, c.visited ? c.colour : 0x8a8f99, c.visited ? 1 : 0.35);
        (c.visited ? scene : missedGroup).add(obj);
        cellObjects.set(c.ray + ':' + c.key, c);
    }
    missedGroup.visible = false;
    scene.add(missedGroup);

    const rodRadius = diag * 0.0025;
    for (const r of data.rays) {
        scene.add(rod(r.from, r.to, rodRadius, r.colour));
        if (r.hit) scene.add(ball(r.hit, rodRadius * 3, r.colour));
    }
    scene.add(ball(data.light, rodRadius * 3, 0xffe14d));

    // The primitives the rays tested: hit ones red, the others blue.
    const primGroup = new THREE.Group();
    const unitSphere = new THREE.SphereGeometry(1, 16, 12);
    for (const p of data.prims) {
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
    scene.add(primGroup);

    const camera = new THREE.PerspectiveCamera(
        45,
        view.clientWidth / view.clientHeight,
        diag * 1e-3,
        diag * 100,
    );
    const target = new THREE.Vector3(...data.view.target);
    camera.position.set(...data.view.eye);
    camera.up.set(...data.view.up);
    const controls = new OrbitControls(camera, renderer.domElement);
    controls.target.copy(target);
    controls.update();

    // The highlight: a translucent box over the named cell, or the named primitive in yellow.
    const highlight = new THREE.Group();
    scene.add(highlight);
    const primById = new Map(data.prims.map((p) => [p.id, p]));
    function show(line) {
        highlight.clear();
        if (!line) return;
        if (line.key) {
            const c = cellObjects.get(line.ray + ':' + line.key);
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

    // The step list: hover shows, click pins. A pinned step is named in the address
    // (#step=N for the primary ray's step N, #shadow=N for the shadow ray's), so a lecturer can
    // link to it and the page opens with it pinned.
    const list = document.getElementById('steps');
    let pinned = null;
    const items = [];
    function pin(i) {
        const was = list.querySelector('li.pinned');
        if (was) was.classList.remove('pinned');
        pinned = pinned === i ? null : i;
        if (pinned !== null) {
            items[i].classList.add('pinned');
            const l = data.lines[i];
            history.replaceState(null, '', '#' + (l.ray ? 'shadow' : 'step') + '=' + l.step);
        } else {
            history.replaceState(null, '', location.pathname + location.search);
        }
        show(pinned === null ? null : data.lines[i]);
        render();
    }
    data.lines.forEach((line, i) => {
        if (line.heading) {
            const h = document.createElement('li');
            h.className = 'heading';
            h.textContent = line.text;
            list.appendChild(h);
            return;
        }
        const li = document.createElement('li');
        li.className = 'step' + (line.key || line.prim >= 0 ? ' names' : '');
        li.textContent = line.text;
        li.dataset.index = String(i);
        li.addEventListener('mouseenter', () => {
            show(line);
            render();
        });
        li.addEventListener('mouseleave', () => {
            show(pinned === null ? null : data.lines[pinned]);
            render();
        });
        li.addEventListener('click', () => pin(i));
        items[i] = li;
        list.appendChild(li);
    });
    const wanted = /^#(step|shadow)=(\d+)$/.exec(location.hash);
    if (wanted) {
        const ray = wanted[1] === 'shadow' ? 1 : 0;
        const step = Number(wanted[2]);
        // The line covering that step: the last one starting at or before it.
        let found = -1;
        data.lines.forEach((l, i) => {
            if (!l.heading && l.ray === ray && l.step <= step) found = i;
        });
        if (found >= 0) {
            pin(found);
            items[found].scrollIntoView({ block: 'center' });
        }
    }

    document.getElementById('show-missed').addEventListener('change', (ev) => {
        missedGroup.visible = ev.target.checked;
        render();
    });
    document.getElementById('show-model').addEventListener('change', (ev) => {
        model.visible = ev.target.checked;
        render();
    });

    render();
    if (document.body.dataset.octrace !== 'error') document.body.dataset.octrace = 'rendered';
}

main();

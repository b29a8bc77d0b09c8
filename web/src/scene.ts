// The 3D scene: the layers stacked in height (mesh at the bottom, then agents, objects, places,
// rooms, building), each with a visibility and a height; nodes as instanced spheres filled by the
// colour mode with a rim in their robot's colour; trajectories, loop closures (kept solid,
// rejected faded), merges as links between the merged copies, rooms as translucent hulls with
// labels, the mesh per robot. While the camera moves the mesh is drawn coarser.
import * as THREE from "three";
import { OrbitControls } from "three/addons/controls/OrbitControls.js";
import { CSS2DObject, CSS2DRenderer } from "three/addons/renderers/CSS2DRenderer.js";
import { labelColour, layerColour, robotColour } from "./colours";
import type { ViewerMesh } from "./mesh";
import { LAYERS, nodes } from "./view";
import type { ClosureRow, EdgeRow, LayerName, MergeRow, NodeRow, View } from "./view";

export type ColourMode = "robot" | "label" | "layer";
export type SceneLayer = LayerName | "mesh" | "edges" | "loop_closures" | "merges";
export const SCENE_LAYERS: SceneLayer[] = ["mesh", ...LAYERS, "edges", "loop_closures", "merges"];

const RADIUS: Record<LayerName, number> = { agents: 0.07, objects: 0.18, places: 0.12, rooms: 0.35, buildings: 0.6 };
export const DEFAULT_HEIGHT: Record<LayerName | "mesh", number> = {
  mesh: 0, agents: 3, objects: 6, places: 9, rooms: 13, buildings: 17,
};
// Above this many faces the mesh is drawn with every k-th face while the camera moves.
const MOVING_FACES = 12000;
// While the camera moves, at most this many nodes per layer and line segments per kind are drawn
// (a uniform sample: they are stored in the order of a hash of their ids).
const MOVING_POINTS = 1500;
const MOVING_SEGMENTS = 1000;
// While the camera moves the picture is drawn at this share of the resolution, then in full.
const MOVING_PIXEL_RATIO = 0.35;

interface RobotMesh {
  full: THREE.Mesh; // every face, on the robot's vertices
  coarseIndex: Uint32Array; // every step-th face, on the team's coarse vertices
  coarseVertices: Uint32Array; // the robot's vertices the coarse faces use
  coarseStart: number; // where they start among the team's coarse vertices
  step: number;
  faces: number; // in the mesh
  drawn: number; // faces drawn (the view's round)
  labels: Uint32Array;
  colours: Uint8Array;
}

export interface DrawnStats {
  seq: number;
  round: number;
  nodes: Record<string, Record<string, number>>; // layer -> robot ("" none) -> drawn
  visible: Record<string, boolean>;
  loopClosures: { intraKept: number; intraRejected: number; interKept: number; interRejected: number };
  merges: number;
  rooms: number;
  meshFaces: Record<string, number>;
  frames: number;
}

export class SceneView {
  readonly renderer: THREE.WebGLRenderer;
  readonly labels: CSS2DRenderer;
  readonly scene = new THREE.Scene();
  readonly camera: THREE.PerspectiveCamera;
  readonly controls: OrbitControls;
  private groups = new Map<SceneLayer, THREE.Group>();
  // What each layer draws fewer of while the camera moves: (moving) => void.
  private lod = new Map<SceneLayer, ((moving: boolean) => void)[]>();
  private heights: Record<LayerName | "mesh", number> = { ...DEFAULT_HEIGHT };
  private visible: Record<string, boolean> = {};
  private colourMode: ColourMode = "robot";
  private view: View | null = null;
  private byId = new Map<string, NodeRow>();
  private pickable: { object: THREE.Points; ids: string[]; layer: LayerName }[] = [];
  private materials = new Map<number, THREE.ShaderMaterial>();
  private robotMeshes = new Map<string, RobotMesh>();
  private coarseMesh: THREE.Mesh | null = null;
  private meshData: ViewerMesh | null = null;
  private selected: THREE.Mesh;
  private selectedId = "";
  private moving = false;
  private dirty = true;
  private fitted = false;
  frames = 0;
  syncFrames = false;
  /** When the first frame with a view and its mesh was drawn (performance.now()), 0 until then. */
  firstFullFrameMs = 0;
  /** Called once right after the next frame is drawn, with its time. */
  afterFrame: ((drawnMs: number) => void)[] = [];
  /** Milliseconds spent per part of the frames drawn (render calls, labels, waiting for the GPU). */
  timings = { render: 0, labels: 0, finish: 0 };
  private pixel = new Uint8Array(4);
  onFrame: (() => void) | null = null;

  constructor(private container: HTMLElement) {
    this.renderer = new THREE.WebGLRenderer({ antialias: false, powerPreference: "high-performance" });
    this.renderer.setPixelRatio(1);
    this.renderer.setSize(container.clientWidth, container.clientHeight);
    container.appendChild(this.renderer.domElement);
    this.labels = new CSS2DRenderer();
    this.labels.setSize(container.clientWidth, container.clientHeight);
    this.labels.domElement.style.position = "absolute";
    this.labels.domElement.style.top = "0";
    this.labels.domElement.style.pointerEvents = "none";
    container.appendChild(this.labels.domElement);
    this.scene.background = new THREE.Color("#101418");
    this.camera = new THREE.PerspectiveCamera(50, container.clientWidth / container.clientHeight, 0.1, 2000);
    this.camera.up.set(0, 0, 1);
    this.camera.position.set(-20, -20, 30);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.addEventListener("change", () => (this.dirty = true));
    this.controls.addEventListener("start", () => this.setMoving(true));
    this.controls.addEventListener("end", () => this.setMoving(false));
    this.scene.add(new THREE.AmbientLight(0xffffff, 0.75));
    const sun = new THREE.DirectionalLight(0xffffff, 1.6);
    sun.position.set(10, -15, 40);
    this.scene.add(sun);
    for (const layer of SCENE_LAYERS) {
      const group = new THREE.Group();
      group.name = layer;
      this.groups.set(layer, group);
      this.scene.add(group);
      this.visible[layer] = true;
    }
    this.selected = new THREE.Mesh(
      new THREE.SphereGeometry(1, 16, 12),
      new THREE.MeshBasicMaterial({ color: 0xffffff, wireframe: true }),
    );
    this.selected.visible = false;
    this.scene.add(this.selected);
    new ResizeObserver(() => this.resize()).observe(container);
    const loop = () => {
      requestAnimationFrame(loop);
      this.onFrame?.();
      if (!this.dirty) return;
      this.dirty = false;
      const t0 = performance.now();
      this.renderer.render(this.scene, this.camera);
      const t1 = performance.now();
      if (!this.moving) this.labels.render(this.scene, this.camera);
      const t2 = performance.now();
      if (this.syncFrames) {
        // Wait for the frame to be drawn (one pixel read back), so frames counted are frames made.
        const gl = this.renderer.getContext();
        gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, this.pixel);
      }
      const t3 = performance.now();
      if (this.firstFullFrameMs === 0 && this.view && this.meshData) this.firstFullFrameMs = t3;
      const after = this.afterFrame.splice(0);
      for (const f of after) f(t3);
      this.timings.render += t1 - t0;
      this.timings.labels += t2 - t1;
      this.timings.finish += t3 - t2;
      ++this.frames;
    };
    loop();
  }

  resize(): void {
    const w = this.container.clientWidth;
    const h = this.container.clientHeight;
    this.renderer.setSize(w, h);
    this.labels.setSize(w, h);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.updatePointScale();
    this.dirty = true;
  }

  invalidate(): void {
    this.dirty = true;
  }

  setMoving(moving: boolean): void {
    if (moving === this.moving) return;
    this.moving = moving;
    this.renderer.setPixelRatio(moving ? MOVING_PIXEL_RATIO : 1);
    // Labels are DOM elements over the canvas: moving them costs the compositor a redraw each.
    this.labels.domElement.style.visibility = moving ? "hidden" : "visible";
    this.renderer.setSize(this.container.clientWidth, this.container.clientHeight);
    this.updatePointScale();
    this.applyDrawRange();
    for (const entries of this.lod.values()) for (const apply of entries) apply(moving);
    this.dirty = true;
  }

  // Draws `count` items of `size` vertices, or a prefix of `budget` of them while moving.
  private budget(layer: SceneLayer, geometry: THREE.BufferGeometry, count: number, size: number, budget: number): void {
    const apply = (moving: boolean) => geometry.setDrawRange(0, size * (moving ? Math.min(count, budget) : count));
    apply(this.moving);
    this.lod.get(layer)!.push(apply);
  }

  setColourMode(mode: ColourMode): void {
    this.colourMode = mode;
    this.rebuild();
    this.recolourMesh();
  }

  setLayerVisible(layer: SceneLayer, visible: boolean): void {
    this.visible[layer] = visible;
    this.groups.get(layer)!.visible = visible;
    if (layer === "rooms") for (const o of this.roomLabels) o.visible = visible;
    this.dirty = true;
  }

  layerVisible(layer: SceneLayer): boolean {
    return this.visible[layer];
  }

  setLayerHeight(layer: LayerName | "mesh", height: number): void {
    this.heights[layer] = height;
    if (layer === "mesh") {
      this.groups.get("mesh")!.position.z = height;
      this.dirty = true;
    } else {
      this.rebuild();
    }
  }

  height(layer: LayerName | "mesh"): number {
    return this.heights[layer];
  }

  node(id: string): NodeRow | undefined {
    return this.byId.get(id);
  }

  currentView(): View | null {
    return this.view;
  }

  /** Where a node is drawn (its layer's height added). */
  positionOf(row: NodeRow): THREE.Vector3 {
    return new THREE.Vector3(row[3] / 100, row[4] / 100, row[5] / 100 + this.heights[row[1]]);
  }

  setView(view: View): void {
    this.view = view;
    this.byId = new Map(nodes(view).map((n) => [n[0], n]));
    this.rebuild();
    for (const [robot, m] of this.robotMeshes) this.updateMeshRange(m, robot);
    if (!this.fitted && this.byId.size > 0) this.fit();
    if (this.selectedId) this.select(this.selectedId);
  }

  private roomLabels: CSS2DObject[] = [];

  private clear(layer: SceneLayer): THREE.Group {
    const group = this.groups.get(layer)!;
    this.lod.set(layer, []);
    group.traverse((o) => {
      if (o instanceof CSS2DObject) o.element.remove();
      const disposable = o as unknown as { geometry?: THREE.BufferGeometry; material?: THREE.Material };
      if (o !== group && disposable.geometry) disposable.geometry.dispose();
    });
    group.clear();
    return group;
  }

  private fill(row: NodeRow): THREE.Color {
    const [, layer, robot, , , , , a] = row;
    if (this.colourMode === "layer") return layerColour(layer);
    if (this.colourMode === "label" && layer !== "agents") return labelColour(a.label);
    if (robot) return robotColour(robot);
    return a.color ? new THREE.Color(a.color) : layerColour(layer);
  }

  private rebuild(): void {
    if (!this.view) return;
    const view = this.view;
    const all = nodes(view);
    this.pickable = [];
    this.roomLabels = [];
    for (const layer of LAYERS) {
      const group = this.clear(layer);
      const rows = all.filter((n) => n[1] === layer).sort((x, y) => hashOf(x[0]) - hashOf(y[0]));
      if (rows.length === 0) continue;
      const positions = new Float32Array(3 * rows.length);
      const fills = new Float32Array(3 * rows.length);
      const rims = new Float32Array(3 * rows.length);
      rows.forEach((row, i) => {
        this.positionOf(row).toArray(positions, 3 * i);
        this.fill(row).toArray(fills, 3 * i);
        robotColour(row[2]).toArray(rims, 3 * i);
      });
      const geometry = new THREE.BufferGeometry();
      geometry.setAttribute("position", new THREE.BufferAttribute(positions, 3));
      geometry.setAttribute("fill", new THREE.BufferAttribute(fills, 3));
      geometry.setAttribute("rim", new THREE.BufferAttribute(rims, 3));
      geometry.computeBoundingSphere();
      const points = new THREE.Points(geometry, this.nodeMaterial(RADIUS[layer]));
      this.budget(layer, geometry, rows.length, 1, MOVING_POINTS);
      group.add(points);
      this.pickable.push({ object: points, ids: rows.map((row) => row[0]), layer });
      if (layer === "agents") this.drawTrajectories(group, rows);
      if (layer === "rooms") this.drawRooms(group, rows, all);
    }
    this.drawEdges(all);
    this.drawLoopClosures(view);
    this.drawMerges(view);
    this.dirty = true;
  }

  // Nodes as round points of `radius` metres, filled by the colour mode, with a rim in their
  // robot's colour: one vertex per node (software rendering draws a sphere per node far slower).
  private nodeMaterial(radius: number): THREE.ShaderMaterial {
    let material = this.materials.get(radius);
    if (material) return material;
    material = new THREE.ShaderMaterial({
      uniforms: { radius: { value: radius }, scale: { value: 1 } },
      vertexShader: `
        attribute vec3 fill;
        attribute vec3 rim;
        uniform float radius;
        uniform float scale;
        varying vec3 vFill;
        varying vec3 vRim;
        void main() {
          vec4 mv = modelViewMatrix * vec4(position, 1.0);
          gl_PointSize = max(3.0, 2.0 * radius * scale / -mv.z);
          gl_Position = projectionMatrix * mv;
          vFill = fill;
          vRim = rim;
        }`,
      fragmentShader: `
        varying vec3 vFill;
        varying vec3 vRim;
        void main() {
          vec2 c = 2.0 * gl_PointCoord - 1.0;
          float r = dot(c, c);
          if (r > 1.0) discard;
          gl_FragColor = vec4(r > 0.5 ? vRim : vFill, 1.0);
        }`,
    });
    this.materials.set(radius, material);
    this.updatePointScale();
    return material;
  }

  // Pixels per metre at distance 1: the points' size follows the perspective.
  private updatePointScale(): void {
    const scale = this.renderer.domElement.height / (2 * Math.tan(THREE.MathUtils.degToRad(this.camera.fov / 2)));
    for (const m of this.materials.values()) m.uniforms.scale.value = scale;
  }

  // Each robot's keyframes in order, as one set of line segments for the whole team (one draw),
  // and a coarser one (every k-th keyframe) for while the camera moves.
  private drawTrajectories(group: THREE.Group, agents: NodeRow[]): void {
    const byRobot = new Map<string, NodeRow[]>();
    for (const a of agents) {
      if (!byRobot.has(a[2])) byRobot.set(a[2], []);
      byRobot.get(a[2])!.push(a);
    }
    const step = Math.max(1, Math.ceil(agents.length / MOVING_SEGMENTS));
    const full: THREE.Vector3[] = [], fullColours: THREE.Color[] = [];
    const coarse: THREE.Vector3[] = [], coarseColours: THREE.Color[] = [];
    for (const [robot, rows] of byRobot) {
      rows.sort((x, y) => (x[7].k ?? 0) - (y[7].k ?? 0));
      const colour = robotColour(robot);
      const sampled = rows.filter((_, i) => i % step === 0 || i === rows.length - 1);
      for (const [list, points, colours] of [[rows, full, fullColours], [sampled, coarse, coarseColours]] as const) {
        for (let i = 1; i < list.length; ++i) {
          points.push(this.positionOf(list[i - 1]), this.positionOf(list[i]));
          colours.push(colour, colour);
        }
      }
    }
    if (full.length === 0) return;
    const fullLines = this.lines(full, fullColours, 1);
    const coarseLines = this.lines(coarse, coarseColours, 1);
    const apply = (moving: boolean) => {
      fullLines.visible = !moving || step === 1;
      coarseLines.visible = moving && step > 1;
    };
    apply(this.moving);
    this.lod.get("agents")!.push(apply);
    group.add(fullLines, coarseLines);
  }

  // Rooms as translucent hulls of their places (one mesh and one outline for all rooms), with
  // labels.
  private drawRooms(group: THREE.Group, rooms: NodeRow[], all: NodeRow[]): void {
    const children = new Map<string, NodeRow[]>();
    for (const n of all) {
      if (n[1] !== "places" || !n[6]) continue;
      if (!children.has(n[6])) children.set(n[6], []);
      children.get(n[6])!.push(n);
    }
    const z = this.heights.rooms - 0.02;
    const surface: number[] = [], surfaceColours: number[] = [];
    const outline: THREE.Vector3[] = [], outlineColours: THREE.Color[] = [];
    for (const room of rooms) {
      const points = (children.get(room[0]) ?? []).map((p) => new THREE.Vector2(p[3] / 100, p[4] / 100));
      const hull = convexHull(points.length >= 3 ? points : square(room[3] / 100, room[4] / 100, 0.5));
      if (hull.length >= 3) {
        const colour = this.colourMode === "layer" ? layerColour("rooms") : labelColour(room[7].label ?? room[0].length);
        for (let i = 1; i + 1 < hull.length; ++i) {  // a fan: the hull is convex
          for (const p of [hull[0], hull[i], hull[i + 1]]) {
            surface.push(p.x, p.y, z);
            surfaceColours.push(colour.r, colour.g, colour.b);
          }
        }
        hull.forEach((p, i) => {
          const q = hull[(i + 1) % hull.length];
          outline.push(new THREE.Vector3(p.x, p.y, z), new THREE.Vector3(q.x, q.y, z));
          outlineColours.push(colour, colour);
        });
      }
      const element = document.createElement("div");
      element.className = "room-label";
      element.textContent = `${room[0]} ${room[7].name ?? ""}`.trim();
      const label = new CSS2DObject(element);
      label.position.copy(this.positionOf(room)).add(new THREE.Vector3(0, 0, 0.6));
      label.visible = this.visible.rooms;
      group.add(label);
      this.roomLabels.push(label);
    }
    if (surface.length > 0) {
      const geometry = new THREE.BufferGeometry();
      geometry.setAttribute("position", new THREE.Float32BufferAttribute(surface, 3));
      geometry.setAttribute("color", new THREE.Float32BufferAttribute(surfaceColours, 3));
      group.add(new THREE.Mesh(geometry, new THREE.MeshBasicMaterial({
        vertexColors: true, transparent: true, opacity: 0.22, side: THREE.DoubleSide, depthWrite: false,
      })));
      group.add(this.lines(outline, outlineColours, 1));
    }
  }

  private lines(points: THREE.Vector3[], colours: THREE.Color[], opacity: number): THREE.LineSegments {
    const geometry = new THREE.BufferGeometry().setFromPoints(points);
    const c = new Float32Array(colours.length * 3);
    colours.forEach((col, i) => col.toArray(c, 3 * i));
    geometry.setAttribute("color", new THREE.BufferAttribute(c, 3));
    return new THREE.LineSegments(geometry, new THREE.LineBasicMaterial({ vertexColors: true, transparent: opacity < 1, opacity }));
  }

  // Line segments (points and colours in pairs), stored in a shuffled order so that the prefix
  // drawn while the camera moves is a uniform sample.
  private segments(layer: SceneLayer, points: THREE.Vector3[], colours: THREE.Color[], opacity: number): THREE.LineSegments {
    const n = points.length / 2;
    const order = shuffledOrder(n);
    const p = new Float32Array(6 * n);
    const c = new Float32Array(6 * n);
    order.forEach((k, i) => {
      points[2 * k].toArray(p, 6 * i);
      points[2 * k + 1].toArray(p, 6 * i + 3);
      colours[2 * k].toArray(c, 6 * i);
      colours[2 * k + 1].toArray(c, 6 * i + 3);
    });
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute("position", new THREE.BufferAttribute(p, 3));
    geometry.setAttribute("color", new THREE.BufferAttribute(c, 3));
    this.budget(layer, geometry, n, 2, MOVING_SEGMENTS);
    return new THREE.LineSegments(
      geometry,
      new THREE.LineBasicMaterial({ vertexColors: true, transparent: opacity < 1, opacity, depthWrite: opacity >= 1 }),
    );
  }

  private drawEdges(all: NodeRow[]): void {
    const group = this.clear("edges");
    const points: THREE.Vector3[] = [];
    const colours: THREE.Color[] = [];
    const grey = new THREE.Color("#6a7682");
    for (const child of all) {
      const parent = child[6] ? this.byId.get(child[6]) : undefined;
      if (!parent) continue;
      points.push(this.positionOf(child), this.positionOf(parent));
      colours.push(grey, grey);
    }
    for (const [a, b] of this.view!.tables.edges.values() as Iterable<EdgeRow>) {
      const x = this.byId.get(a);
      const y = this.byId.get(b);
      if (!x || !y) continue;
      points.push(this.positionOf(x), this.positionOf(y));
      colours.push(grey, grey);
    }
    if (points.length > 0) group.add(this.segments("edges", points, colours, 0.22));
  }

  private drawLoopClosures(view: View): void {
    const group = this.clear("loop_closures");
    const kept: THREE.Vector3[] = [], keptColours: THREE.Color[] = [];
    const rejected: THREE.Vector3[] = [], rejectedColours: THREE.Color[] = [];
    const inter = new THREE.Color("#ffffff");
    for (const [from, to, isInter, isKept] of view.tables.loop_closures.values() as Iterable<ClosureRow>) {
      const a = this.byId.get(from);
      const b = this.byId.get(to);
      if (!a || !b) continue;
      const points = isKept ? kept : rejected;
      const colours = isKept ? keptColours : rejectedColours;
      points.push(this.positionOf(a), this.positionOf(b));
      const c = isInter ? inter : robotColour(a[2]);
      colours.push(c, c);
    }
    if (kept.length > 0) group.add(this.segments("loop_closures", kept, keptColours, 1));
    if (rejected.length > 0) group.add(this.segments("loop_closures", rejected, rejectedColours, 0.18));
  }

  private drawMerges(view: View): void {
    const group = this.clear("merges");
    const points: THREE.Vector3[] = [];
    const colours: THREE.Color[] = [];
    for (const row of view.tables.merges.values() as Iterable<MergeRow>) {
      const [target, source, layer, tx, ty, tz, sx, sy, sz] = row;
      const h = this.heights[layer] ?? 0;
      points.push(new THREE.Vector3(tx / 100, ty / 100, tz / 100 + h), new THREE.Vector3(sx / 100, sy / 100, sz / 100 + h));
      colours.push(robotColour(robotOf(target)), robotColour(robotOf(source)));
    }
    if (points.length > 0) group.add(this.segments("merges", points, colours, 1));
  }

  // --- the mesh ---

  // The mesh: per robot all its faces; for while the camera moves, every step-th face of the team
  // in one draw, on a compact copy of the vertices they use.
  setMesh(mesh: ViewerMesh): void {
    this.meshData = mesh;
    const group = this.clear("mesh");
    this.robotMeshes.clear();
    const step = Math.max(1, Math.ceil(mesh.faces / MOVING_FACES));
    const material = new THREE.MeshBasicMaterial({ vertexColors: true, side: THREE.DoubleSide });
    const coarsePositions: number[] = [];
    for (const [robot, [vStart, vCount, fStart, fCount]] of Object.entries(mesh.robots)) {
      if (vCount === 0 || fCount === 0) continue;
      const positions = mesh.positions.subarray(3 * vStart, 3 * (vStart + vCount));
      const index = new Uint32Array(3 * fCount);
      const source = mesh.indices.subarray(3 * fStart, 3 * (fStart + fCount));
      for (let i = 0; i < index.length; ++i) index[i] = source[i] - vStart;
      const geometry = new THREE.BufferGeometry();
      geometry.setAttribute("position", new THREE.BufferAttribute(positions, 3));
      geometry.setAttribute("color", new THREE.BufferAttribute(new Uint8Array(3 * vCount), 3, true));
      geometry.setIndex(new THREE.BufferAttribute(index, 1));
      const coarseStart = coarsePositions.length / 3;
      const used = new Map<number, number>();
      const coarseIndex = new Uint32Array(3 * Math.ceil(fCount / step));
      for (let f = 0, j = 0; f < fCount; f += step) {
        for (let k = 0; k < 3; ++k, ++j) {
          const v = index[3 * f + k];
          let c = used.get(v);
          if (c === undefined) {
            used.set(v, (c = used.size));
            coarsePositions.push(positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]);
          }
          coarseIndex[j] = coarseStart + c;
        }
      }
      const coarseVertices = new Uint32Array(used.size);
      for (const [v, c] of used) coarseVertices[c] = v;
      const full = new THREE.Mesh(geometry, material);
      full.frustumCulled = false;
      group.add(full);
      this.robotMeshes.set(robot, {
        full, coarseIndex, coarseVertices, coarseStart, step, faces: fCount, drawn: fCount,
        labels: mesh.labels.subarray(vStart, vStart + vCount),
        colours: mesh.colours.subarray(3 * vStart, 3 * (vStart + vCount)),
      });
    }
    const coarseGeometry = new THREE.BufferGeometry();
    coarseGeometry.setAttribute("position", new THREE.Float32BufferAttribute(coarsePositions, 3));
    coarseGeometry.setAttribute("color", new THREE.BufferAttribute(new Uint8Array(coarsePositions.length), 3, true));
    this.coarseMesh = new THREE.Mesh(coarseGeometry, material);
    this.coarseMesh.frustumCulled = false;
    group.add(this.coarseMesh);
    for (const [robot, m] of this.robotMeshes) this.updateMeshRange(m, robot);
    group.position.z = this.heights.mesh;
    this.recolourMesh();
    this.dirty = true;
  }

  private updateMeshRange(m: RobotMesh, robot: string): void {
    const extent = this.view?.mesh?.[robot];
    m.drawn = extent ? Math.min(extent[3], m.faces) : this.view ? 0 : m.faces;
    this.applyDrawRange();
  }

  // Each robot's faces up to the view's round; the coarse mesh's index is made of the same
  // prefixes.
  private applyDrawRange(): void {
    const coarse = this.moving && this.coarseMesh !== null;
    let size = 0;
    for (const m of this.robotMeshes.values()) {
      m.full.visible = !coarse;
      m.full.geometry.setDrawRange(0, 3 * m.drawn);
      size += 3 * Math.ceil(m.drawn / m.step);
    }
    if (this.coarseMesh) {
      this.coarseMesh.visible = coarse;
      if (coarse) {
        const index = new Uint32Array(size);
        let at = 0;
        for (const m of this.robotMeshes.values()) {
          const n = 3 * Math.ceil(m.drawn / m.step);
          index.set(m.coarseIndex.subarray(0, n), at);
          at += n;
        }
        this.coarseMesh.geometry.setIndex(new THREE.BufferAttribute(index, 1));
      }
    }
    this.dirty = true;
  }

  private recolourMesh(): void {
    for (const [robot, m] of this.robotMeshes) {
      const attr = m.full.geometry.getAttribute("color") as THREE.BufferAttribute;
      const out = attr.array as Uint8Array;
      const tint = robotColour(robot);
      const tr = tint.r * 255, tg = tint.g * 255, tb = tint.b * 255;
      const palette = new Map<number, THREE.Color>();
      for (let i = 0; i < m.labels.length; ++i) {
        let r = m.colours[3 * i], g = m.colours[3 * i + 1], b = m.colours[3 * i + 2];
        if (this.colourMode === "robot") {
          r = 0.55 * r + 0.45 * tr; g = 0.55 * g + 0.45 * tg; b = 0.55 * b + 0.45 * tb;
        } else if (this.colourMode === "label") {
          const label = m.labels[i];
          if (!palette.has(label)) palette.set(label, labelColour(label));
          const c = palette.get(label)!;
          r = c.r * 255; g = c.g * 255; b = c.b * 255;
        }
        out[3 * i] = r; out[3 * i + 1] = g; out[3 * i + 2] = b;
      }
      attr.needsUpdate = true;
      if (this.coarseMesh) {
        const coarse = this.coarseMesh.geometry.getAttribute("color") as THREE.BufferAttribute;
        const to = coarse.array as Uint8Array;
        m.coarseVertices.forEach((v, c) => to.set(out.subarray(3 * v, 3 * v + 3), 3 * (m.coarseStart + c)));
        coarse.needsUpdate = true;
      }
    }
    this.dirty = true;
  }

  // --- camera, picking, selection ---

  fit(): void {
    const box = new THREE.Box3();
    for (const n of this.byId.values()) box.expandByPoint(this.positionOf(n));
    if (this.meshData) {
      const p = this.meshData.positions;
      for (let i = 0; i < p.length; i += 3 * 97) box.expandByPoint(new THREE.Vector3(p[i], p[i + 1], p[i + 2]));
    }
    if (box.isEmpty()) return;
    const centre = box.getCenter(new THREE.Vector3());
    const size = box.getSize(new THREE.Vector3()).length();
    this.controls.target.copy(centre);
    this.camera.position.copy(centre).add(new THREE.Vector3(-0.45 * size, -0.75 * size, 0.6 * size));
    this.camera.far = Math.max(2000, 10 * size);
    this.camera.updateProjectionMatrix();
    this.controls.update();
    this.fitted = true;
    this.dirty = true;
  }

  pick(clientX: number, clientY: number): string | null {
    const rect = this.renderer.domElement.getBoundingClientRect();
    const ndc = new THREE.Vector2(((clientX - rect.left) / rect.width) * 2 - 1, -((clientY - rect.top) / rect.height) * 2 + 1);
    const ray = new THREE.Raycaster();
    ray.setFromCamera(ndc, this.camera);
    // The nearest node whose drawn disc holds the pixel, over the visible layers.
    let best: string | null = null;
    let bestDepth = Infinity;
    for (const target of this.pickable) {
      if (!this.visible[target.layer]) continue;
      ray.params.Points = { threshold: RADIUS[target.layer] };
      for (const hit of ray.intersectObject(target.object, false)) {
        if (hit.index === undefined || hit.distanceToRay === undefined) continue;
        if (hit.distance < bestDepth) {
          bestDepth = hit.distance;
          best = target.ids[hit.index];
        }
      }
    }
    return best;
  }

  /** Screen position (client pixels) of a node, or null when it is not drawn. */
  screenPositionOf(id: string): { x: number; y: number } | null {
    const row = this.byId.get(id);
    if (!row) return null;
    const p = this.positionOf(row).project(this.camera);
    const rect = this.renderer.domElement.getBoundingClientRect();
    return { x: rect.left + ((p.x + 1) / 2) * rect.width, y: rect.top + ((1 - p.y) / 2) * rect.height };
  }

  select(id: string | null): void {
    this.selectedId = id ?? "";
    const row = id ? this.byId.get(id) : undefined;
    this.selected.visible = !!row;
    if (row) {
      const r = RADIUS[row[1]] * 2.2;
      this.selected.scale.set(r, r, r);
      this.selected.position.copy(this.positionOf(row));
    }
    this.dirty = true;
  }

  focus(id: string): void {
    const row = this.byId.get(id);
    if (!row) return;
    const p = this.positionOf(row);
    this.camera.position.add(p.clone().sub(this.controls.target));
    this.controls.target.copy(p);
    this.controls.update();
    this.dirty = true;
  }

  /** What is drawn, for the tests and the benchmark. */
  stats(): DrawnStats {
    const counts: Record<string, Record<string, number>> = {};
    for (const p of this.pickable) {
      const perRobot: Record<string, number> = (counts[p.layer] ??= {});
      for (let i = 0; i < p.object.geometry.getAttribute("position").count; ++i) {
        const robot = this.byId.get(p.ids[i])?.[2] ?? "?";
        perRobot[robot] = (perRobot[robot] ?? 0) + 1;
      }
    }
    const lc = { intraKept: 0, intraRejected: 0, interKept: 0, interRejected: 0 };
    for (const [from, to, inter, kept] of (this.view?.tables.loop_closures.values() ?? []) as Iterable<ClosureRow>) {
      if (!this.byId.has(from) || !this.byId.has(to)) continue;
      if (inter) kept ? ++lc.interKept : ++lc.interRejected;
      else kept ? ++lc.intraKept : ++lc.intraRejected;
    }
    const meshFaces: Record<string, number> = {};
    for (const [robot, m] of this.robotMeshes) meshFaces[robot] = m.drawn;
    const visible: Record<string, boolean> = {};
    for (const [layer, group] of this.groups) visible[layer] = group.visible;
    return {
      seq: this.view?.seq ?? 0,
      round: this.view?.round ?? 0,
      nodes: counts,
      visible,
      loopClosures: lc,
      merges: this.view?.tables.merges.size ?? 0,
      rooms: this.roomLabels.length,
      meshFaces,
      frames: this.frames,
    };
  }
}

/** FNV-1a of a string: a stable pseudo-random order of nodes. */
function hashOf(text: string): number {
  let h = 0x811c9dc5;
  for (let i = 0; i < text.length; ++i) h = Math.imul(h ^ text.charCodeAt(i), 0x01000193);
  return h >>> 0;
}

/** 0..n-1 in a fixed shuffled order (a linear congruential walk). */
function shuffledOrder(n: number): number[] {
  const order = Array.from({ length: n }, (_, i) => i);
  let state = 12345;
  for (let i = n - 1; i > 0; --i) {
    state = (Math.imul(state, 1103515245) + 12345) >>> 0;
    const j = state % (i + 1);
    [order[i], order[j]] = [order[j], order[i]];
  }
  return order;
}

export function robotOf(id: string): string {
  const at = id.indexOf("@");
  if (at >= 0) return id.slice(at + 1);
  return /^[a-oq-z]\d+$/.test(id) ? id[0] : "";
}

function square(x: number, y: number, r: number): THREE.Vector2[] {
  return [new THREE.Vector2(x - r, y - r), new THREE.Vector2(x + r, y - r), new THREE.Vector2(x + r, y + r), new THREE.Vector2(x - r, y + r)];
}

/** Andrew's monotone chain, counter-clockwise. */
export function convexHull(points: THREE.Vector2[]): THREE.Vector2[] {
  const p = [...points].sort((a, b) => a.x - b.x || a.y - b.y);
  if (p.length < 3) return p;
  const cross = (o: THREE.Vector2, a: THREE.Vector2, b: THREE.Vector2) => (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
  const lower: THREE.Vector2[] = [];
  for (const q of p) {
    while (lower.length >= 2 && cross(lower[lower.length - 2], lower[lower.length - 1], q) <= 0) lower.pop();
    lower.push(q);
  }
  const upper: THREE.Vector2[] = [];
  for (let i = p.length - 1; i >= 0; --i) {
    while (upper.length >= 2 && cross(upper[upper.length - 2], upper[upper.length - 1], p[i]) <= 0) upper.pop();
    upper.push(p[i]);
  }
  return lower.slice(0, -1).concat(upper.slice(0, -1));
}

// The viewer's model of one backend round, as the station sends it (docs/VIEWER.md, mirrored from
// src/hydra_multi/web/view_state.h): tables of rows keyed by id, and the round's figures. A
// snapshot replaces the view; a delta sets and deletes rows and replaces the figures.

export type TableName = "nodes" | "edges" | "loop_closures" | "merges";
export const TABLES: TableName[] = ["nodes", "edges", "loop_closures", "merges"];
export const LAYERS = ["agents", "objects", "places", "rooms", "buildings"] as const;
export type LayerName = (typeof LAYERS)[number];

export interface NodeAttributes {
  active?: boolean;
  label?: number;
  name?: string;
  color?: string;
  box?: [number, number, number];
  t?: number;
  k?: number;
  q?: [number, number, number, number];
  vertices?: number;
  distance?: number;
}
/** [id, layer, robot, x, y, z (cm), parent, attributes] */
export type NodeRow = [string, LayerName, string, number, number, number, string, NodeAttributes];
/** [from, to, inter (0/1), kept (0/1)] */
export type ClosureRow = [string, string, number, number];
/** [target, source, layer, tx, ty, tz, sx, sy, sz (cm)] */
export type MergeRow = [string, string, LayerName, number, number, number, number, number, number];
export type EdgeRow = [string, string];
type Row = unknown[];

export interface RobotInfo {
  aligned?: boolean;
  applied?: number;
  next_sequence?: number;
  robot_time_s?: number;
  connected?: boolean;
  silent_s?: number;
  bytes?: number;
  done?: boolean;
}

export interface View {
  seq: number;
  round: number;
  final: boolean;
  info: Record<string, number>;
  robots: Record<string, RobotInfo>;
  mesh: Record<string, [number, number, number, number]>;
  tables: Record<TableName, Map<string, Row>>;
}

export interface Delta {
  seq: number;
  round: number;
  final: boolean;
  snapshot?: boolean;
  info: Record<string, number>;
  robots: Record<string, RobotInfo>;
  mesh: Record<string, [number, number, number, number]>;
  set: Partial<Record<TableName, Row[]>>;
  del: Partial<Record<TableName, string[]>>;
}

export function keyOf(table: TableName, row: Row): string {
  return table === "nodes" ? String(row[0]) : `${row[0]}|${row[1]}`;
}

export function emptyView(): View {
  return {
    seq: 0,
    round: 0,
    final: false,
    info: {},
    robots: {},
    mesh: {},
    tables: { nodes: new Map(), edges: new Map(), loop_closures: new Map(), merges: new Map() },
  };
}

/** Applies a delta in place (a snapshot starts from the empty view); returns the view. */
export function applyDelta(view: View, delta: Delta): View {
  const next = delta.snapshot ? emptyView() : view;
  for (const table of TABLES) {
    for (const row of delta.set[table] ?? []) next.tables[table].set(keyOf(table, row), row);
    for (const key of delta.del[table] ?? []) next.tables[table].delete(key);
  }
  next.seq = delta.seq;
  next.round = delta.round;
  next.final = delta.final;
  next.info = delta.info;
  next.robots = delta.robots;
  next.mesh = delta.mesh;
  return next;
}

export function nodes(view: View): NodeRow[] {
  return [...view.tables.nodes.values()] as NodeRow[];
}

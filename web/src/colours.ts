// One colour per robot used everywhere (trajectory, mesh tint, node rim), and colours by
// semantic label and by layer.
import { Color } from "three";
import type { LayerName } from "./view";

const ROBOT_COLOURS = [
  "#e6194b", "#3cb44b", "#4363d8", "#f58231", "#911eb4", "#42d4f4", "#f032e6", "#bfef45",
  "#fabed4", "#469990", "#dcbeff", "#9a6324", "#fffac8", "#800000", "#aaffc3", "#808000",
  "#ffd8b1", "#000075", "#a9a9a9", "#ffe119", "#ffffff", "#008080", "#e6beff", "#aa6e28", "#00ff7f",
];

export function robotColour(robot: string): Color {
  if (!robot) return new Color("#b0b0b0");
  const index = robot.charCodeAt(0) - "a".charCodeAt(0);
  return new Color(ROBOT_COLOURS[((index % ROBOT_COLOURS.length) + ROBOT_COLOURS.length) % ROBOT_COLOURS.length]);
}

export function robotCss(robot: string): string {
  return `#${robotColour(robot).getHexString()}`;
}

/** A stable colour per label id (golden-ratio hues). */
export function labelColour(label: number | undefined): Color {
  if (label === undefined || label === 0xffffffff) return new Color("#808080");
  const hue = (label * 0.618033988749895) % 1;
  return new Color().setHSL(hue, 0.65, 0.55);
}

const LAYER_COLOURS: Record<LayerName | "mesh", string> = {
  mesh: "#8a8a8a",
  agents: "#ffcc00",
  objects: "#ff5577",
  places: "#33bbff",
  rooms: "#66dd66",
  buildings: "#cc88ff",
};

export function layerColour(layer: LayerName | "mesh"): Color {
  return new Color(LAYER_COLOURS[layer]);
}

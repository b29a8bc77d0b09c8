// A small line chart in SVG: one polyline per series over a shared x axis, with the y maximum.
const NS = "http://www.w3.org/2000/svg";

export function drawLineChart(svg: SVGSVGElement, series: Record<string, [number, number][]>, colours: Record<string, string>): void {
  const width = svg.width.baseVal.value;
  const height = svg.height.baseVal.value;
  const pad = { left: 30, right: 4, top: 6, bottom: 12 };
  svg.replaceChildren();
  const all = Object.values(series).flat();
  if (all.length === 0) return;
  const xMin = Math.min(...all.map((p) => p[0]));
  const xMax = Math.max(...all.map((p) => p[0]), xMin + 1);
  const yMax = Math.max(...all.map((p) => p[1]), 1e-9);
  const x = (v: number) => pad.left + ((v - xMin) / (xMax - xMin)) * (width - pad.left - pad.right);
  const y = (v: number) => height - pad.bottom - (v / yMax) * (height - pad.top - pad.bottom);
  const text = (content: string, tx: number, ty: number, anchor = "start") => {
    const t = document.createElementNS(NS, "text");
    t.setAttribute("x", String(tx));
    t.setAttribute("y", String(ty));
    t.setAttribute("text-anchor", anchor);
    t.textContent = content;
    svg.append(t);
  };
  const axis = document.createElementNS(NS, "path");
  axis.setAttribute("d", `M${pad.left},${pad.top} V${height - pad.bottom} H${width - pad.right}`);
  axis.setAttribute("stroke", "#55606a");
  axis.setAttribute("fill", "none");
  svg.append(axis);
  text(yMax >= 10 ? yMax.toFixed(0) : yMax.toPrecision(2), pad.left - 3, pad.top + 6, "end");
  text("0", pad.left - 3, height - pad.bottom, "end");
  text(`view ${xMax}`, width - pad.right, height - 1, "end");
  for (const [name, points] of Object.entries(series)) {
    const line = document.createElementNS(NS, "polyline");
    line.setAttribute("points", points.map(([a, b]) => `${x(a).toFixed(1)},${y(b).toFixed(1)}`).join(" "));
    line.setAttribute("fill", "none");
    line.setAttribute("stroke", colours[name] ?? "#ccc");
    line.setAttribute("stroke-width", "1.5");
    line.dataset.series = name;
    svg.append(line);
  }
}

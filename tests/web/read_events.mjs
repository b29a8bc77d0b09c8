// Reads a viewer's event stream (GET /api/events) until it has a view and a status event naming
// every robot given, then prints one line: "events: a snapshot, N deltas; status: a connected,
// b connected". Exits 1 after `seconds` without them.
//   node read_events.mjs URL SECONDS ROBOT...
const [url, seconds, ...robots] = process.argv.slice(2);
const timer = setTimeout(() => {
  console.log(`events: not all of ${robots.join(", ")} in a status event within ${seconds} s`);
  process.exit(1);
}, Number(seconds) * 1000);
const response = await fetch(`${url}api/events`);
const decoder = new TextDecoder();
let text = "", snapshots = 0, deltas = 0;
for await (const chunk of response.body) {
  text += decoder.decode(chunk, { stream: true });
  let end;
  while ((end = text.indexOf("\n\n")) >= 0) {
    const block = text.slice(0, end);
    text = text.slice(end + 2);
    const type = /^event: (.*)$/m.exec(block)?.[1];
    const data = /^data: (.*)$/m.exec(block)?.[1];
    if (type === "snapshot") ++snapshots;
    if (type === "delta") ++deltas;
    if (type !== "status" || snapshots === 0) continue;
    const links = JSON.parse(data).robots;
    if (robots.every((r) => links[r])) {
      console.log(`events: ${snapshots} snapshot, ${deltas > 0 ? "deltas" : "no deltas yet"}; status: ${robots.map((r) => `${r} ${links[r].connected ? "connected" : "silent"}`).join(", ")}`);
      clearTimeout(timer);
      process.exit(0);
    }
  }
}

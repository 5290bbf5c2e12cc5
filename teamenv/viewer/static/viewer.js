// The teamenv replay viewer: loads a replay from the local server and plays it on a canvas.
// Plain JavaScript, no build step. `window.teamenvViewer` exposes the state for tests.
"use strict";

(function () {
  const TEAM_COLOURS = ["rgb(40,90,220)", "rgb(220,50,50)"];
  const TEAM_RGB = [[40, 90, 220], [220, 50, 50]];
  const GRASS = "rgb(30,120,40)";
  const LINE = "rgb(235,235,235)";
  const GOAL = "rgb(250,250,120)";
  const MARGIN_M = 1.0;      // grass drawn around the pitch, metres
  const PLAYER_RADIUS_M = 0.2;
  const SPEEDS = [0.25, 0.5, 1, 2, 4, 8, 16, 32];

  const $ = (id) => document.getElementById(id);
  const canvas = $("pitch");
  const ctx = canvas.getContext("2d");

  // Everything a test may read; positions in field coordinates (metres, radians).
  const state = {
    ready: false,          // a replay is loaded and drawn (it can play)
    overlaysLoaded: false, // its overlay arrays (falls, messages, beliefs, roles) are in too
    error: null,           // the last error message shown to the user
    source: null,          // /api/source
    matches: [],           // /api/matches
    matchId: null,
    header: null,
    nCycles: 0,
    cycle: 0,
    playing: false,
    speed: 1,
    selected: null,        // index of the selected player, or null
    stats: null,           // MatchStats JSON, or null
    drawn: null,           // {cycle, ball: [x, y], players: [[x, y, heading], ...], ...}
    overlays: {},
    timing: {},            // milliseconds since navigation started (performance.now())
  };
  let arrays = {};
  let cyclePos = 0;        // fractional cycle while playing
  let lastTick = null;
  let geometry = null;     // pixel transform of the current canvas size
  let loadToken = 0;

  // ---------------------------------------------------------------- loading
  async function fetchJSON(url) {
    const res = await fetch(url);
    const body = await res.json().catch(() => ({ error: `${url}: HTTP ${res.status}` }));
    if (!res.ok) {
      const err = new Error(body.error || `${url}: HTTP ${res.status}`);
      err.status = res.status;
      throw err;
    }
    return body;
  }

  // One group's blob ("core": what playing needs; "overlays": falls, messages, beliefs,
  // roles) as typed-array views, by name.
  async function fetchArrays(id, header, group) {
    const res = await fetch(`/api/matches/${id}/arrays/${group}`);
    if (!res.ok) {
      const body = await res.json().catch(() => ({}));
      throw new Error(body.error || `${group} arrays of match ${id}: HTTP ${res.status}`);
    }
    const buffer = await res.arrayBuffer();
    if (buffer.byteLength !== header.bytes[group]) {
      throw new Error(`${group} arrays of match ${id}: got ${buffer.byteLength} bytes, ` +
        `expected ${header.bytes[group]}`);
    }
    const out = {};
    for (const spec of header.arrays) {
      if (spec.group !== group) continue;
      const Type = window[spec.dtype];
      const count = spec.shape.reduce((a, b) => a * b, 1);
      out[spec.name] = new Type(buffer, spec.offset, count);
    }
    return out;
  }

  function setStatus(text, isError) {
    const el = $("status");
    el.textContent = text || "";
    el.className = isError ? "error" : "";
    if (isError) state.error = text;
  }

  async function openMatch(id) {
    const token = ++loadToken;
    pause();
    state.ready = false;
    state.error = null;
    setStatus(`loading match ${id}…`);
    try {
      const header = await fetchJSON(`/api/matches/${id}/header`);
      state.timing.headerMs = performance.now();
      const data = await fetchArrays(id, header, "core");
      if (token !== loadToken) return;
      state.timing.arraysMs = performance.now();
      arrays = data;
      state.overlaysLoaded = false;
      state.header = header;
      state.matchId = id;
      state.nCycles = header.cycles;
      state.selected = null;
      state.stats = null;
      $("seek").max = String(header.cycles - 1);
      renderMatchInfo();
      renderMatchList();
      renderAgent();
      seek(0);
      state.ready = true;
      state.timing.readyMs = performance.now();
      setStatus("");
      loadOverlays(id, header, token);
      loadStats(id, token);
    } catch (err) {
      if (token === loadToken) setStatus(err.message, true);
      throw err;
    }
  }

  // The overlay arrays arrive while the match already plays; then they are drawn too.
  async function loadOverlays(id, header, token) {
    try {
      const data = await fetchArrays(id, header, "overlays");
      if (token !== loadToken) return;
      Object.assign(arrays, data);
      state.overlaysLoaded = true;
      state.timing.overlaysMs = performance.now();
      draw();
      renderAgent();
    } catch (err) {
      if (token === loadToken) setStatus(err.message, true);
    }
  }

  async function loadStats(id, token) {
    const body = $("stats-body");
    body.textContent = "computing…";
    try {
      const stats = await fetchJSON(`/api/matches/${id}/stats`);
      if (token !== loadToken) return;
      state.stats = stats;
      body.replaceChildren(statsTable(stats));
    } catch (err) {
      if (token !== loadToken) return;
      body.textContent = err.status === 404 ? "not available: " + err.message : err.message;
    }
  }

  // ---------------------------------------------------------------- playback
  function play() {
    if (!state.ready) return;
    if (state.cycle >= state.nCycles - 1) seek(0);
    state.playing = true;
    cyclePos = state.cycle;
    lastTick = null;
    $("play").textContent = "Pause";
  }

  function pause() {
    state.playing = false;
    $("play").textContent = "Play";
  }

  function seek(cycle) {
    const c = Math.max(0, Math.min(state.nCycles - 1, Math.round(Number(cycle) || 0)));
    state.cycle = c;
    cyclePos = c;
    $("seek").value = String(c);
    draw();
    return c;
  }

  function setSpeed(speed) {
    state.speed = Number(speed);
    $("speed").value = String(state.speed);
  }

  function tick(now) {
    if (state.playing && state.ready) {
      if (lastTick !== null) {
        cyclePos += ((now - lastTick) / 1000) * state.speed / state.header.cycle_s;
        const next = Math.min(state.nCycles - 1, Math.floor(cyclePos));
        if (next !== state.cycle) {
          state.cycle = next;
          $("seek").value = String(next);
          draw();
          if (state.timing.playingMs === undefined) state.timing.playingMs = performance.now();
        }
        if (next >= state.nCycles - 1) pause();
      }
      lastTick = now;
    }
    requestAnimationFrame(tick);
  }

  // ---------------------------------------------------------------- drawing
  function layout() {
    const f = state.header.field;
    const cssWidth = canvas.clientWidth || 900;
    const dpr = window.devicePixelRatio || 1;
    const width = Math.round(cssWidth * dpr);
    const scale = width / (f.length + 2 * MARGIN_M);
    const bar = Math.round(26 * dpr);
    const height = Math.round((f.width + 2 * MARGIN_M) * scale) + bar;
    if (canvas.width !== width || canvas.height !== height) {
      canvas.width = width;
      canvas.height = height;
    }
    geometry = { scale, dpr, bar, ox: width / 2, oy: bar + (height - bar) / 2 };
  }

  // Field coordinates (m) -> canvas pixels.
  function toPixel(x, y) {
    return [geometry.ox + x * geometry.scale, geometry.oy - y * geometry.scale];
  }

  function toField(px, py) {
    return [(px - geometry.ox) / geometry.scale, (geometry.oy - py) / geometry.scale];
  }

  function overlay(name) {
    return $("ov-" + name).checked;
  }

  function drawPitch() {
    const f = state.header.field;
    const hl = f.length / 2, hw = f.width / 2;
    ctx.fillStyle = GRASS;
    ctx.fillRect(0, 0, canvas.width, canvas.height);
    ctx.strokeStyle = LINE;
    ctx.lineWidth = 2 * geometry.dpr;
    const poly = (points, close) => {
      ctx.beginPath();
      points.forEach(([x, y], i) => {
        const [px, py] = toPixel(x, y);
        if (i === 0) ctx.moveTo(px, py); else ctx.lineTo(px, py);
      });
      if (close) ctx.closePath();
      ctx.stroke();
    };
    poly([[-hl, hw], [hl, hw], [hl, -hw], [-hl, -hw]], true);
    poly([[0, hw], [0, -hw]], false);
    const [cx, cy] = toPixel(0, 0);
    ctx.beginPath();
    ctx.arc(cx, cy, f.center_circle_radius * geometry.scale, 0, 2 * Math.PI);
    ctx.stroke();
    for (const sign of [-1, 1]) {
      const x0 = sign * hl, x1 = sign * (hl - f.penalty_length), pw = f.penalty_width / 2;
      poly([[x0, pw], [x1, pw], [x1, -pw], [x0, -pw]], false);
      const gx = sign * (hl + f.goal_depth), gw = f.goal_width / 2;
      ctx.strokeStyle = GOAL;
      ctx.lineWidth = 3 * geometry.dpr;
      poly([[x0, gw], [gx, gw], [gx, -gw], [x0, -gw]], false);
      ctx.strokeStyle = LINE;
      ctx.lineWidth = 2 * geometry.dpr;
    }
  }

  function agentName(i) {
    const n = state.header.team_size;
    return i < n ? `left_${i + 1}` : `right_${i - n + 1}`;
  }

  function playerPose(c, i) {
    const p = arrays.players, n2 = 2 * state.header.team_size, k = (c * n2 + i) * 3;
    return [p[k], p[k + 1], p[k + 2]];
  }

  function beliefPose(c, i) {
    if (!arrays.belief_pose) return null;
    const k = (c * 2 * state.header.team_size + i) * 3, b = arrays.belief_pose;
    return Number.isNaN(b[k]) ? null : [b[k], b[k + 1], b[k + 2]];
  }

  function beliefBall(c, i) {
    if (!arrays.belief_ball) return null;
    const k = (c * 2 * state.header.team_size + i) * 2, b = arrays.belief_ball;
    return Number.isNaN(b[k]) ? null : [b[k], b[k + 1]];
  }

  function roleOf(c, i) {
    if (!arrays.role) return null;
    const r = arrays.role[c * 2 * state.header.team_size + i];
    return r < 0 ? null : r;
  }

  // Speakers (player indices) that player i heard in cycle c (itself excluded).
  function heardBy(c, i) {
    if (!arrays.heard_from) return [];
    const n2 = 2 * state.header.team_size, mask = arrays.heard_from[c * n2 + i], out = [];
    for (let k = 0; k < n2; k++) if (k !== i && (mask >>> k) & 1) out.push(k);
    return out;
  }

  // The latest cycle <= c (at most `back` cycles earlier) in which player i heard anyone:
  // {cycle, speakers}, or null. The channel delivers every other cycle at best, so lines and
  // the panel show the last delivery instead of blinking.
  const HEARD_LOOKBACK = 50;
  function lastHeard(c, i, back) {
    for (let k = c; k >= Math.max(0, c - back); k--) {
      const speakers = heardBy(k, i);
      if (speakers.length) return { cycle: k, speakers };
    }
    return null;
  }

  function withAlpha(rgb, a) {
    return `rgba(${rgb[0]},${rgb[1]},${rgb[2]},${a})`;
  }

  function followed(i) {
    return state.selected === null || state.selected === i;
  }

  function draw() {
    if (!state.header) return;
    layout();
    const h = state.header, c = state.cycle, n = h.team_size, n2 = 2 * n;
    const s = geometry.scale, dpr = geometry.dpr;
    const radius = Math.max(6 * dpr, PLAYER_RADIUS_M * s);
    drawPitch();
    const shown = {
      cone: overlay("cone") && !!h.view_cone, belief: overlay("belief") && !!arrays.belief_pose,
      role: overlay("role") && !!arrays.role, heard: overlay("heard") && !!arrays.heard_from,
      numbers: overlay("numbers"), headings: overlay("headings"), trail: overlay("trail"),
    };
    state.overlays = shown;
    const players = [];
    for (let i = 0; i < n2; i++) players.push(playerPose(c, i));
    const ball = [arrays.ball[c * 4], arrays.ball[c * 4 + 1]];

    if (shown.cone && state.selected !== null) {  // the selected agent's field of view
      const half = h.view_cone.half_angle, reach = Math.max(h.field.length, h.field.width);
      for (const i of [state.selected]) {
        const [x, y, hd] = players[i];
        const [px, py] = toPixel(x, y);
        ctx.fillStyle = withAlpha(TEAM_RGB[i < n ? 0 : 1], 0.2);
        ctx.beginPath();
        ctx.moveTo(px, py);
        ctx.arc(px, py, reach * s, -(hd + half), -(hd - half));  // canvas y points down
        ctx.closePath();
        ctx.fill();
      }
    }
    if (shown.trail) {
      ctx.strokeStyle = "rgba(255,255,255,0.5)";
      ctx.lineWidth = 1.5 * dpr;
      ctx.beginPath();
      for (let k = Math.max(0, c - 250); k <= c; k++) {
        const [px, py] = toPixel(arrays.ball[k * 4], arrays.ball[k * 4 + 1]);
        if (k === Math.max(0, c - 250)) ctx.moveTo(px, py); else ctx.lineTo(px, py);
      }
      ctx.stroke();
    }
    const heard = [];
    if (shown.heard && state.selected === null && arrays.say_bytes) {  // who spoke this cycle
      ctx.fillStyle = "rgb(255,230,80)";
      for (let i = 0; i < n2; i++) {
        if (!arrays.say_bytes[c * n2 + i]) continue;
        const [px, py] = toPixel(players[i][0], players[i][1]);
        ctx.beginPath(); ctx.arc(px - radius, py - radius, 2.5 * dpr, 0, 2 * Math.PI); ctx.fill();
      }
    }
    if (shown.heard && state.selected !== null) {  // a line from each speaker to the selected
      ctx.lineWidth = 1.5 * dpr;
      for (let i = 0; i < n2; i++) {
        if (state.selected !== i) continue;
        const last = lastHeard(c, i, 10);
        for (const k of last ? last.speakers : []) {
          heard.push([k, i]);
          const [ax, ay] = toPixel(players[k][0], players[k][1]);
          const [bx, by] = toPixel(players[i][0], players[i][1]);
          ctx.strokeStyle = withAlpha([255, 230, 80], 0.8);
          ctx.setLineDash([6 * dpr, 4 * dpr]);
          ctx.beginPath(); ctx.moveTo(ax, ay); ctx.lineTo(bx, by); ctx.stroke();
          ctx.setLineDash([]);
        }
      }
    }
    const beliefs = [];
    if (shown.belief) {  // believed pose (hollow) joined to the true one; believed ball
      for (let i = 0; i < n2; i++) {
        if (!followed(i)) continue;
        const rgb = TEAM_RGB[i < n ? 0 : 1], pose = beliefPose(c, i), bb = beliefBall(c, i);
        beliefs.push({ agent: i, pose, ball: bb });
        ctx.lineWidth = 1.5 * dpr;
        if (pose) {
          const [tx, ty] = toPixel(players[i][0], players[i][1]);
          const [bx, by] = toPixel(pose[0], pose[1]);
          ctx.strokeStyle = withAlpha(rgb, 0.9);
          ctx.setLineDash([3 * dpr, 3 * dpr]);
          ctx.beginPath(); ctx.moveTo(tx, ty); ctx.lineTo(bx, by); ctx.stroke();
          ctx.setLineDash([]);
          ctx.strokeStyle = "white";
          ctx.beginPath(); ctx.arc(bx, by, radius, 0, 2 * Math.PI); ctx.stroke();
          ctx.strokeStyle = withAlpha(rgb, 1);
          ctx.beginPath(); ctx.arc(bx, by, radius - 1.5 * dpr, 0, 2 * Math.PI); ctx.stroke();
        }
        if (bb) {
          const [bx, by] = toPixel(bb[0], bb[1]);
          ctx.strokeStyle = withAlpha(rgb, 0.9);
          ctx.beginPath(); ctx.arc(bx, by, Math.max(3 * dpr, 0.11 * s), 0, 2 * Math.PI); ctx.stroke();
        }
      }
    }
    ctx.font = `${Math.round(11 * dpr)}px sans-serif`;
    for (let i = 0; i < n2; i++) {
      const [x, y, hd] = players[i];
      const [px, py] = toPixel(x, y);
      ctx.fillStyle = TEAM_COLOURS[i < n ? 0 : 1];
      ctx.beginPath(); ctx.arc(px, py, radius, 0, 2 * Math.PI); ctx.fill();
      if (arrays.fallen && arrays.fallen[c * n2 + i]) {
        ctx.strokeStyle = "black";
        ctx.lineWidth = 2 * dpr;
        ctx.beginPath(); ctx.arc(px, py, radius, 0, 2 * Math.PI); ctx.stroke();
      }
      if (state.selected === i) {
        ctx.strokeStyle = "white";
        ctx.lineWidth = 2 * dpr;
        ctx.beginPath(); ctx.arc(px, py, radius + 3 * dpr, 0, 2 * Math.PI); ctx.stroke();
      }
      if (shown.headings) {  // a tick outside the disc, so the disc's centre keeps its colour
        ctx.strokeStyle = LINE;
        ctx.lineWidth = 2 * dpr;
        ctx.beginPath();
        ctx.moveTo(px + Math.cos(hd) * radius * 0.5, py - Math.sin(hd) * radius * 0.5);
        ctx.lineTo(px + Math.cos(hd) * radius * 1.6, py - Math.sin(hd) * radius * 1.6);
        ctx.stroke();
      }
      const labels = [];
      if (shown.numbers) labels.push(String((i % n) + 1));
      if (shown.role && roleOf(c, i) !== null) labels.push("r" + roleOf(c, i));
      if (labels.length) {
        ctx.fillStyle = LINE;
        ctx.fillText(labels.join(" "), px + radius, py - radius - 2 * dpr);
      }
    }
    const [bx, by] = toPixel(ball[0], ball[1]);
    ctx.fillStyle = "white";
    ctx.beginPath(); ctx.arc(bx, by, Math.max(3 * dpr, 0.11 * s), 0, 2 * Math.PI); ctx.fill();

    const score = [arrays.score[c * 2], arrays.score[c * 2 + 1]];
    const mode = h.play_modes[arrays.play_mode[c]] || String(arrays.play_mode[c]);
    const time = arrays.time_s[c];
    ctx.fillStyle = LINE;
    ctx.font = `${Math.round(14 * dpr)}px sans-serif`;
    ctx.fillText(`${h.left} ${score[0]} - ${score[1]} ${h.right}    ${time.toFixed(2)} s    ${mode}`,
      8 * dpr, 18 * dpr);
    $("cycle-display").textContent =
      `cycle ${c} / ${state.nCycles - 1}   ${time.toFixed(2)} s   ${mode}`;
    state.drawn = { cycle: c, ball, players, score, mode, time_s: time, beliefs, heard,
      radiusPx: radius };
    if (state.selected !== null) renderAgent();
  }

  // ---------------------------------------------------------------- panels
  function el(tag, text, cls) {
    const e = document.createElement(tag);
    if (text !== undefined && text !== null) e.textContent = String(text);
    if (cls) e.className = cls;
    return e;
  }

  function row(cells, header) {
    const tr = el("tr");
    cells.forEach((v, k) => {
      const td = el(header ? "th" : "td", v);
      if (k > 0 && typeof v === "number") td.className = "num";
      tr.appendChild(td);
    });
    return tr;
  }

  function fmt(v) {
    if (typeof v === "number") return Number.isInteger(v) ? v : Number(v.toFixed(3));
    if (v === null || v === undefined) return "—";
    if (typeof v === "object") return JSON.stringify(v);
    return v;
  }

  function renderMatchInfo() {
    const h = state.header, body = $("match-body");
    const result = h.result || {};
    $("match-title").textContent = `${h.left} vs ${h.right} (seed ${h.seed}, match ${h.id})`;
    const t = el("table");
    const score = result.score ? result.score.join(" - ") : "—";
    [["teams", `${h.left} vs ${h.right}`], ["score", score], ["seed", h.seed],
     ["field", h.field.name], ["team size", h.team_size], ["cycles", h.cycles],
     ["observation", (h.options || {}).observation_mode || "state"],
     ["view cone", h.view_cone ? `${h.view_cone.fov_deg}° (${h.view_cone.profile})` : "—"],
     ["forfeit", result.forfeit ? JSON.stringify(result.forfeit) : "—"]]
      .forEach((r) => t.appendChild(row(r)));
    body.replaceChildren(t);
    const goals = h.events.goal_cycle || [];
    if (goals.length) {
      const list = el("div");
      list.appendChild(el("span", "goals: "));
      goals.forEach((gc, k) => {
        const b = el("button", `${h.events.goal_team[k] === 0 ? h.left : h.right} @ ${gc}`, "link");
        b.type = "button";
        b.addEventListener("click", () => { pause(); seek(Math.max(0, gc - 100)); });
        list.appendChild(b);
        list.appendChild(document.createTextNode(" "));
      });
      body.appendChild(list);
    }
  }

  function renderAgent() {
    const body = $("agent-body"), i = state.selected;
    if (i === null || !state.header) { body.textContent = "no agent selected (click a player)"; return; }
    const c = state.cycle, [x, y, hd] = playerPose(c, i), t = el("table");
    t.appendChild(row(["agent", agentName(i)]));
    t.appendChild(row(["true pose", `${x.toFixed(2)}, ${y.toFixed(2)} m, ${(hd * 180 / Math.PI).toFixed(0)}°`]));
    const pose = beliefPose(c, i);
    if (arrays.belief_pose) {
      t.appendChild(row(["believed pose", pose ? `${pose[0].toFixed(2)}, ${pose[1].toFixed(2)} m, `
        + `error ${Math.hypot(pose[0] - x, pose[1] - y).toFixed(2)} m` : "not given"]));
    }
    const bb = beliefBall(c, i);
    if (arrays.belief_ball) {
      const ball = [arrays.ball[c * 4], arrays.ball[c * 4 + 1]];
      t.appendChild(row(["believed ball", bb ? `${bb[0].toFixed(2)}, ${bb[1].toFixed(2)} m, `
        + `error ${Math.hypot(bb[0] - ball[0], bb[1] - ball[1]).toFixed(2)} m` : "not given"]));
    }
    if (arrays.role) t.appendChild(row(["role", fmt(roleOf(c, i))]));
    if (arrays.heard_from) {
      const last = lastHeard(c, i, HEARD_LOOKBACK);
      const names = last ? last.speakers.map((k) => {
        const n2 = 2 * state.header.team_size;
        const bytes = arrays.say_bytes ? arrays.say_bytes[last.cycle * n2 + k] : 0;
        return bytes ? `${agentName(k)} (${bytes} B)` : agentName(k);
      }) : [];
      const when = last && last.cycle !== c ? ` (cycle ${last.cycle})` : "";
      t.appendChild(row(["heard", names.length ? names.join(", ") + when
        : `nothing in the last ${HEARD_LOOKBACK} cycles`]));
    }
    if (!arrays.belief_pose && !arrays.role && !arrays.heard_from) {
      t.appendChild(row(["overlays", "this replay has no belief, role or message records"]));
    }
    body.replaceChildren(t);
  }

  // MatchStats.to_json(): one row per number of `teams.left` / `teams.right` (dicts of
  // numbers become "name: key" rows, per-player lists are left out), then the match's numbers.
  function statsTable(stats) {
    const t = el("table");
    const teams = stats && stats.teams;
    if (teams && teams.left && teams.right) {
      t.appendChild(row(["", teams.left.team || "left", teams.right.team || "right"], true));
      const label = (k) => k.replace(/_/g, " ");
      for (const [k, v] of Object.entries(teams.left)) {
        if (k === "side" || k === "team" || Array.isArray(v)) continue;
        const w = teams.right[k];
        if (v !== null && typeof v === "object") {
          for (const [sub, x] of Object.entries(v)) {
            if (x !== null && typeof x === "object") {  // e.g. set plays: awarded (taken)
              const y = (w || {})[sub] || {};
              if (!x.awarded && !y.awarded) continue;
              t.appendChild(row([`${label(k)}: ${sub} (taken)`, `${fmt(x.awarded)} (${fmt(x.taken)})`,
                `${fmt(y.awarded)} (${fmt(y.taken)})`]));
            } else {
              t.appendChild(row([`${label(k)}: ${label(sub)}`, fmt(x), fmt((w || {})[sub])]));
            }
          }
        } else {
          t.appendChild(row([label(k), fmt(v), fmt(w)]));
        }
      }
    }
    for (const [k, v] of Object.entries(stats || {})) {
      if (k === "teams" || (v !== null && typeof v === "object")) continue;
      t.appendChild(row([k.replace(/_/g, " "), fmt(v), ""]));
    }
    return t;
  }

  function renderMatchList() {
    const body = $("matches-body");
    if (!state.matches.length) { body.textContent = "no matches"; return; }
    const t = el("table");
    t.appendChild(row(["id", "tournament", "match", "score", "seed", "replay"], true));
    for (const m of state.matches) {
      const tr = row([m.id, m.tournament || "—", m.label, m.score ? m.score.join("-") : "—",
        m.seed, m.replay]);
      tr.className = "match-row" + (m.id === state.matchId ? " current" : "");
      tr.dataset.matchId = String(m.id);
      tr.addEventListener("click", () => openMatch(m.id).catch(() => {}));
      t.appendChild(tr);
    }
    body.replaceChildren(t);
  }

  // ---------------------------------------------------------------- input
  function bindControls() {
    $("play").addEventListener("click", () => (state.playing ? pause() : play()));
    $("seek").addEventListener("input", (e) => { seek(e.target.value); });
    $("speed").addEventListener("change", (e) => setSpeed(e.target.value));
    for (const box of document.querySelectorAll("#overlays input")) {
      box.addEventListener("change", () => draw());
    }
    canvas.addEventListener("click", (e) => {
      if (!state.ready) return;
      const rect = canvas.getBoundingClientRect();
      const px = (e.clientX - rect.left) * canvas.width / rect.width;
      const py = (e.clientY - rect.top) * canvas.height / rect.height;
      const [fx, fy] = toField(px, py);
      let best = null, bestD = 1.0;  // metres
      state.drawn.players.forEach(([x, y], i) => {
        const d = Math.hypot(x - fx, y - fy);
        if (d < bestD) { best = i; bestD = d; }
      });
      select(best);
    });
    window.addEventListener("keydown", (e) => {
      // a focused button, slider, check box or menu keeps its own keys (no double steps)
      if (!state.ready || ["BUTTON", "INPUT", "SELECT"].includes(e.target.tagName)) return;
      if (e.key === " ") { e.preventDefault(); state.playing ? pause() : play(); }
      else if (e.key === "ArrowRight" || e.key === "ArrowLeft") {
        e.preventDefault();
        const step = (e.shiftKey ? Math.round(1 / state.header.cycle_s) : 1) * (e.key === "ArrowRight" ? 1 : -1);
        seek(state.cycle + step);
      } else if (e.key === "[" || e.key === "]") {
        const k = SPEEDS.indexOf(state.speed) + (e.key === "]" ? 1 : -1);
        if (k >= 0 && k < SPEEDS.length) setSpeed(SPEEDS[k]);
      }
    });
    window.addEventListener("resize", () => draw());
  }

  function select(i) {
    state.selected = i === undefined ? null : i;
    draw();
    renderAgent();
  }

  async function start() {
    bindControls();
    requestAnimationFrame(tick);
    const params = new URLSearchParams(window.location.search);
    try {
      state.source = await fetchJSON("/api/source");
      state.matches = await fetchJSON("/api/matches");
      if (state.source.kind === "tournament") {  // the list first: it is what one picks from
        $("matches").parentNode.prepend($("matches"));
      }
      renderMatchList();
      const wanted = params.has("match") ? Number(params.get("match")) : state.source.default_match;
      if (params.has("speed")) setSpeed(params.get("speed"));
      if (wanted === null || wanted === undefined) {
        $("match-title").textContent = "pick a match on the right";
        return;
      }
      await openMatch(wanted);
      if (params.has("cycle")) seek(params.get("cycle"));
      if (params.get("autoplay") === "1") play();
    } catch (err) {
      setStatus(err.message, true);
    }
  }

  window.teamenvViewer = {
    state, play, pause, seek, setSpeed, openMatch, select, toPixel,
    // The team colours as [r, g, b] (left, right), for pixel checks.
    teamColours: TEAM_RGB,
  };
  start();
})();

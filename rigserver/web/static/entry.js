// rig: the readings typed at the stand, on a run's page. Plain script, no build step.
//
// Each channel group has a form, one input per channel. A cell is checked as it is typed
// against the channel's limits (the stand's declaration, the one the server checks a batch
// against, handed to the page in data-limit); a decimal comma is a decimal point. Enter
// moves to the next cell and, on the last, keeps the row: first in the browser's IndexedDB
// with its seq (fixed there, once: a row sent again is stored once by the server), then it
// is sent, in the order typed, to the page's own /runs/{id}/rows. A row the server has not
// answered for stays in IndexedDB and is sent once it answers, also after the page was
// closed and opened again. A row the server holds carries its index in its group as stored
// (data-index, each cell too: a one-row group's values come from several rows), the address
// of a correction: "Correct" and "Strike out" open an inline form with the row's cells and
// a reason (Enter saves, Escape cancels), checked as a typed row is and sent to the page's
// /runs/{id}/readings/{group}/{index}(/strike). The value as typed stays shown, struck
// through, beside the corrected one.
(function () {
  "use strict";

  const config = JSON.parse(document.getElementById("entry-config").textContent);
  const text = config.text;
  const status = document.getElementById("entry-status");
  const plural = new Intl.PluralRules(config.lang);
  const forms = Array.from(document.querySelectorAll("form.entry-row"));
  const RETRY_MS = 2000;
  const SEQ_BLOCK = 2147483648; // 2^31 seqs per browser and run; the block is random
  let db = null;
  let sending = false;
  let again = false;
  let retry = null;
  let stopped = "";
  let offline = false;
  let waiting = 0;

  function fill(template, values) {
    return template.replace(/\{(\w+)\}/g, (m, k) => (k in values ? String(values[k]) : m));
  }

  function shown(value) {
    return String(value).replace(".", config.decimal);
  }

  // --- the browser's store of the rows not yet acknowledged -------------------------------
  function request(r) {
    return new Promise((resolve, reject) => {
      r.onsuccess = () => resolve(r.result);
      r.onerror = () => reject(r.error);
    });
  }

  function openDb() {
    const opening = indexedDB.open("rig-entry", 1);
    opening.onupgradeneeded = () => {
      const rows = opening.result.createObjectStore("rows", { keyPath: "n", autoIncrement: true });
      rows.createIndex("run", "run");
      opening.result.createObjectStore("writers", { keyPath: "run" });
    };
    return request(opening);
  }

  function randomBlock() {
    const value = new Uint32Array(1);
    crypto.getRandomValues(value);
    return (value[0] % 2097151) + 1; // 1 .. 2^21 - 1: seq stays below 2^52, exact in JSON
  }

  // Keep a row: its seq is the browser's block for the run and the next number in it, taken
  // in the same transaction as the row is added (two tabs cannot take one number).
  function keep(group, columns, cells) {
    return new Promise((resolve, reject) => {
      const tx = db.transaction(["rows", "writers"], "readwrite");
      const writers = tx.objectStore("writers");
      const record = { run: config.run, group: group, columns: columns, cells: cells, state: "waiting" };
      writers.get(config.run).onsuccess = (event) => {
        const writer = event.target.result || { run: config.run, block: randomBlock(), next: 0 };
        record.seq = writer.block * SEQ_BLOCK + writer.next;
        writer.next += 1;
        writers.put(writer);
        tx.objectStore("rows").add(record).onsuccess = (added) => { record.n = added.target.result; };
      };
      tx.oncomplete = () => resolve(record);
      tx.onerror = () => reject(tx.error);
      tx.onabort = () => reject(tx.error);
    });
  }

  async function kept() {
    const tx = db.transaction("rows", "readonly");
    const rows = await request(tx.objectStore("rows").index("run").getAll(config.run));
    return rows.sort((a, b) => a.n - b.n);
  }

  function change(store, write) {
    return new Promise((resolve, reject) => {
      const tx = db.transaction(store, "readwrite");
      write(tx.objectStore(store));
      tx.oncomplete = () => resolve();
      tx.onerror = () => reject(tx.error);
    });
  }

  // --- the table of the rows received ------------------------------------------------------
  function tableRow(record) {
    const form = forms.find((f) => f.dataset.group === record.group);
    if (!form) return null;
    let tr = form.querySelector("tbody tr[data-n='" + record.n + "']");
    if (tr) return tr;
    tr = document.createElement("tr");
    tr.dataset.n = String(record.n);
    for (const input of form.querySelectorAll("tfoot input")) {
      const td = document.createElement("td");
      td.className = "num";
      td.dataset.channel = input.name;
      td.textContent = record.cells[input.name] || "";
      tr.appendChild(td);
    }
    tr.appendChild(document.createElement("td"));
    form.querySelector("tbody").appendChild(tr);
    return tr;
  }

  function showRow(record, state, reason, index) {
    const tr = tableRow(record);
    if (!tr) return;
    tr.className = state;
    const last = tr.lastElementChild;
    last.textContent = state === "sent" ? text.sent : state === "waiting" ? text.waits : fill(text.refused, { reason: reason });
    if (state === "sent" && index !== undefined) {
      tr.dataset.index = String(index);
      for (const td of tr.querySelectorAll("td.num")) {
        if (td.textContent === "") continue;
        td.dataset.index = String(index);
        td.dataset.value = td.textContent;
      }
      offer(tr);
    }
    if (state === "refused") {
      const drop = document.createElement("button");
      drop.type = "button";
      drop.textContent = text.dismiss;
      drop.addEventListener("click", async () => {
        await change("rows", (store) => store.delete(record.n));
        tr.remove();
      });
      last.appendChild(document.createTextNode(" "));
      last.appendChild(drop);
    }
  }

  function waitingText(n) {
    return fill(config.waiting[plural.select(n)], { n: n });
  }

  function showStatus() {
    status.dataset.waiting = String(waiting);
    const parts = [];
    if (waiting > 0) parts.push(waitingText(waiting));
    else parts.push(text.all_sent);
    if (stopped) parts.push(fill(text.stopped, { reason: stopped }));
    else if (offline && waiting > 0) parts.push(text.offline);
    status.textContent = parts.join(" — ");
    status.className = stopped ? "refused" : offline && waiting > 0 ? "offline" : "";
  }

  // --- sending, in the order typed ----------------------------------------------------------
  // A JSON body posted as the page's session: its form token in the X-Rig-Form header.
  function post(url, body) {
    return fetch(url, {
      method: "POST",
      credentials: "same-origin",
      cache: "no-store",
      headers: { "Content-Type": "application/json", "X-Rig-Form": config.form_token },
      body: JSON.stringify(body),
    });
  }

  function later() {
    if (retry === null) retry = window.setTimeout(() => { retry = null; send(); }, RETRY_MS);
  }

  // Send what is kept, one row after the other; a call while sending makes the sending go
  // round once more (a row kept meanwhile is not left behind).
  async function send() {
    if (db === null) return;
    if (sending) {
      again = true;
      return;
    }
    sending = true;
    try {
      do {
        again = false;
        await sendKept();
      } while (again && !stopped && !offline);
    } finally {
      sending = false;
    }
    showStatus();
  }

  async function sendKept() {
    for (;;) {
      const rows = (await kept()).filter((r) => r.state === "waiting");
      waiting = rows.length;
      showStatus();
      if (!rows.length || stopped) break;
      const row = rows[0];
      let answer;
      try {
        answer = await post(config.rows_url, { seq: row.seq, group: row.group, columns: row.columns });
      } catch (error) {
        offline = true;
        later();
        break;
      }
      if (answer.status === 200 || answer.status === 201) {
        offline = false;
        let receipt = {};
        try { receipt = await answer.json(); } catch (error) { receipt = {}; }
        await change("rows", (store) => store.delete(row.n));
        // a retry's receipt counts the rows stored since: its index is the page's on reload
        showRow(row, "sent", "", receipt.duplicate ? undefined : receipt.group_rows - 1);
        document.dispatchEvent(new CustomEvent("rig:row-stored", { detail: row.group }));
        continue;
      }
      let message = "";
      try { message = (await answer.json()).message || ""; } catch (error) { message = ""; }
      if (answer.status === 422 || answer.status === 413) {
        offline = false;
        row.state = "refused";
        row.reason = message;
        await change("rows", (store) => store.put(row));
        showRow(row, "refused", message);
        continue;
      }
      if (answer.status >= 500 || answer.status === 429 || !message) {
        offline = true; // a proxy's or an overloaded server's answer: try again
        later();
        break;
      }
      stopped = message; // the session, the key's scope, the run's state: a person acts
      break;
    }
  }

  // --- checking the cells as they are typed --------------------------------------------------
  const NUMBER = /^[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$/;

  function parse(raw) {
    const cleaned = raw.trim().replace(",", ".").replace("\u2212", "-");
    if (!NUMBER.test(cleaned)) return null;
    const value = Number(cleaned);
    return isFinite(value) ? value : null;
  }

  // The refusal of a cell's text, "" if it holds (an empty cell holds until the row is sent).
  function refusal(input, raw) {
    if (raw.trim() === "") return "";
    const value = parse(raw);
    if (value === null) return fill(text.not_a_number, { value: raw.trim() });
    const limit = JSON.parse(input.dataset.limit);
    const say = { symbol: input.dataset.symbol, value: shown(value), unit: input.dataset.unit };
    if (limit.low !== null && value < limit.low) return fill(text.below, { ...say, low: shown(limit.low) });
    if (limit.high !== null && value > limit.high) return fill(text.above, { ...say, high: shown(limit.high) });
    if (limit.nominal !== null) {
      const near = limit.nominal.some((v) => Math.abs(value - v) <= limit.tolerance * Math.abs(v));
      if (!near) return fill(text.nominal, { ...say, values: limit.nominal.map(shown).join(", ") });
    }
    if (limit.integer && value !== Math.round(value)) return fill(text.integer, say);
    return "";
  }

  function mark(input, message) {
    const beside = document.getElementById(input.getAttribute("aria-describedby"));
    if (message) input.setAttribute("aria-invalid", "true");
    else input.removeAttribute("aria-invalid");
    beside.textContent = message;
  }

  function check(input) {
    const message = refusal(input, input.value);
    mark(input, message);
    return message === "";
  }

  // The row of a form if every cell holds (its columns, and the cells as typed), else null
  // with the refusals shown and the first refused cell focused.
  function row(form) {
    const inputs = Array.from(form.querySelectorAll("tfoot input"));
    const aligned = form.dataset.aligned === "true";
    const required = JSON.parse(form.dataset.required);
    let bad = inputs.filter((input) => !check(input));
    const filled = inputs.filter((input) => input.value.trim() !== "");
    if (!bad.length && aligned) {
      const names = filled.map((input) => input.name);
      const complete = required.length
        ? required.some((set) => set.every((name) => names.includes(name)))
        : filled.length === inputs.length;
      if (!complete) {
        bad = inputs.filter((input) => input.value.trim() === "" &&
          (!required.length || required.some((set) => set.includes(input.name))));
        for (const input of bad) mark(input, text.empty);
      }
    } else if (!bad.length && !filled.length) {
      bad = [inputs[0]];
      mark(inputs[0], text.one_value);
    }
    if (bad.length) {
      bad[0].focus();
      return null;
    }
    const columns = {};
    const cells = {};
    for (const input of filled) {
      columns[input.name] = [parse(input.value)];
      cells[input.name] = shown(parse(input.value));
    }
    return { columns: columns, cells: cells };
  }

  // Keep the row the form holds and send it. The cells are emptied at once, before the row
  // is in IndexedDB: the next row may already be typed while it is stored.
  async function submit(form) {
    const found = row(form);
    if (found === null) return;
    const inputs = Array.from(form.querySelectorAll("tfoot input"));
    const typedCells = inputs.map((input) => input.value);
    for (const input of inputs) {
      input.value = "";
      mark(input, "");
    }
    inputs[0].focus();
    waiting += 1; // counted from now: the row is in hand
    showStatus();
    let record;
    try {
      record = await keep(form.dataset.group, found.columns, found.cells);
    } catch (error) {
      inputs.forEach((input, i) => { if (input.value === "") input.value = typedCells[i]; });
      waiting -= 1;
      status.textContent = String(error);
      return;
    }
    showRow(record, "waiting");
    send();
  }

  for (const form of forms) {
    const inputs = Array.from(form.querySelectorAll("tfoot input"));
    form.addEventListener("submit", (event) => {
      event.preventDefault();
      submit(form);
    });
    inputs.forEach((input, i) => {
      input.addEventListener("input", () => check(input));
      input.addEventListener("keydown", (event) => {
        if (event.key !== "Enter") return;
        event.preventDefault();
        if (i + 1 < inputs.length) {
          check(input); // a refused cell keeps its message; the row waits for it at the end
          inputs[i + 1].focus();
        } else {
          submit(form);
        }
      });
    });
  }

  // --- corrections of the rows the server holds ----------------------------------------------
  function offer(tr) {
    const last = tr.lastElementChild;
    if (tr.classList.contains("struck") || !tr.querySelector("td[data-index]")) return;
    if (last.querySelector("button.correct")) return;
    for (const kind of ["correct", "strike"]) {
      const button = document.createElement("button");
      button.type = "button";
      button.className = kind;
      button.textContent = text[kind];
      button.addEventListener("click", () => edit(tr, kind, button));
      last.appendChild(document.createTextNode(" "));
      last.appendChild(button);
    }
  }

  function refusalSpan(id) {
    const span = document.createElement("span");
    span.className = "refusal";
    span.id = id;
    return span;
  }

  // The inline form of a row: its cells (to correct) or none (to strike out), and a reason.
  function edit(tr, kind, button) {
    const form = tr.closest("form");
    const group = form.dataset.group;
    for (const open of form.querySelectorAll("tr.correcting")) open.remove();
    const editor = document.createElement("tr");
    editor.className = "correcting " + kind;
    const inputs = [];
    for (const td of tr.querySelectorAll("td.num")) {
      const cell = document.createElement("td");
      if (kind === "correct" && td.dataset.index !== undefined) {
        const typedInput = form.querySelector("tfoot input[name='" + td.dataset.channel + "']");
        const input = document.createElement("input");
        input.name = td.dataset.channel;
        input.id = "fix-" + group + "-" + input.name;
        input.value = td.dataset.value;
        input.size = 7;
        input.inputMode = "decimal";
        input.autocomplete = "off";
        for (const key of ["limit", "symbol", "unit"]) input.dataset[key] = typedInput.dataset[key];
        input.setAttribute("aria-label", typedInput.labels[0].querySelector(".visually-hidden").textContent);
        input.setAttribute("aria-describedby", "fix-err-" + group + "-" + input.name);
        input.addEventListener("input", () => check(input));
        cell.appendChild(input);
        cell.appendChild(refusalSpan("fix-err-" + group + "-" + input.name));
        inputs.push({ input: input, td: td });
      }
      editor.appendChild(cell);
    }
    const last = document.createElement("td");
    const reason = document.createElement("input");
    reason.name = "reason";
    reason.id = "fix-" + group + "-reason";
    reason.required = true;
    reason.maxLength = 500;
    reason.placeholder = text.reason;
    reason.setAttribute("aria-label", text.reason);
    reason.setAttribute("aria-describedby", "fix-err-" + group + "-reason");
    last.appendChild(reason);
    const saveButton = document.createElement("button");
    saveButton.type = "button";
    saveButton.textContent = text.save;
    const cancelButton = document.createElement("button");
    cancelButton.type = "button";
    cancelButton.textContent = text.cancel;
    last.append(" ", saveButton, " ", cancelButton, refusalSpan("fix-err-" + group + "-reason"));
    editor.appendChild(last);
    tr.after(editor);

    // back to the button; a struck row has none left: to the group's first cell
    const close = () => {
      editor.remove();
      (button.isConnected ? button : form.querySelector("tfoot input")).focus();
    };
    const save = () => saveEdit(tr, kind, editor, inputs, reason, close);
    saveButton.addEventListener("click", save);
    cancelButton.addEventListener("click", close);
    editor.addEventListener("keydown", (event) => {
      if (event.key === "Escape") {
        event.preventDefault();
        close();
      } else if (event.key === "Enter" && event.target.tagName === "INPUT") {
        event.preventDefault();
        save();
      }
    });
    (inputs.length ? inputs[0].input : reason).focus();
  }

  async function saveEdit(tr, kind, editor, inputs, reason, close) {
    const group = tr.closest("form").dataset.group;
    let bad = null;
    const changes = new Map(); // the row as stored -> its cells' new values
    for (const { input, td } of inputs) {
      const message = input.value.trim() === "" ? text.empty : refusal(input, input.value);
      mark(input, message);
      if (message) {
        bad = bad || input;
        continue;
      }
      const value = parse(input.value);
      if (value === parse(td.dataset.value)) continue;
      const values = changes.get(td.dataset.index) || {};
      values[input.name] = value;
      changes.set(td.dataset.index, values);
    }
    const why = reason.value.trim();
    mark(reason, why ? "" : text.reason_needed);
    if (!why) bad = bad || reason;
    if (!bad && kind === "correct" && changes.size === 0) {
      mark(reason, text.no_change);
      bad = inputs.length ? inputs[0].input : reason;
    }
    if (bad) {
      bad.focus();
      return;
    }
    const indices = kind === "strike"
      ? Array.from(new Set(Array.from(tr.querySelectorAll("td[data-index]"), (td) => td.dataset.index)))
      : Array.from(changes.keys());
    for (const index of indices) {
      const body = kind === "strike" ? { reason: why } : { values: changes.get(index), reason: why };
      const url = config.readings_url + "/" + encodeURIComponent(group) + "/" + index +
        (kind === "strike" ? "/strike" : "") + "?lang=" + config.lang;
      let answer;
      try {
        answer = await post(url, body);
      } catch (error) {
        mark(reason, text.offline);
        return;
      }
      let found = {};
      try { found = await answer.json(); } catch (error) { found = {}; }
      if (!answer.ok) {
        const cell = inputs.find((i) => i.input.name === found.channel);
        const target = cell ? cell.input : reason;
        mark(target, found.message || fill(text.refused, { reason: answer.status }));
        target.focus();
        return;
      }
      corrected(tr, found);
    }
    close();
    document.dispatchEvent(new CustomEvent("rig:row-stored", { detail: group }));
  }

  // Show a row as the server now reads it: each corrected cell its value after the one
  // typed, struck through, whose title gives the reasons; a struck row struck out.
  function corrected(tr, row) {
    for (const td of tr.querySelectorAll("td.num[data-index='" + row.index + "']")) {
      const name = td.dataset.channel;
      const now = row.values[name];
      const reasons = row.corrections.filter((c) => c.channel === name).map((c) => c.reason);
      td.textContent = "";
      if (reasons.length) {
        const was = document.createElement("s");
        was.className = "typed";
        was.title = fill(text.corrected_title, { reason: reasons.join("; ") });
        was.textContent = shown(row.original[name]);
        td.append(was, " ");
      }
      const value = document.createElement("span");
      value.className = "value";
      value.textContent = shown(now);
      td.appendChild(value);
      td.dataset.value = shown(now);
    }
    const strike = row.corrections.filter((c) => c.channel === null).pop();
    if (row.struck && strike) {
      tr.classList.add("struck");
      tr.title = fill(text.struck_title, { reason: strike.reason });
      tr.lastElementChild.textContent = text.struck;
    }
  }

  // --- finish and abort: asked once, and not while rows wait -------------------------------
  for (const end of document.querySelectorAll("form.end")) {
    end.addEventListener("submit", (event) => {
      if (waiting > 0) {
        event.preventDefault();
        status.textContent = fill(text.wait_first, { waiting: waitingText(waiting) });
        return;
      }
      if (!window.confirm(text[end.dataset.confirm])) event.preventDefault();
    });
  }

  for (const tr of document.querySelectorAll("form.entry-row tbody tr.sent")) offer(tr);
  window.addEventListener("online", () => send());
  openDb().then(async (opened) => {
    db = opened;
    for (const record of await kept()) showRow(record, record.state, record.reason || "");
    send();
  });
})();

// A series page while a member run is open: fetch the page again every few seconds and put
// its tables and plots in place of the old ones; stop once no member run is open.
"use strict";
(function () {
  const body = document.getElementById("series-body");
  if (!body) return;
  function schedule(seconds) {
    if (seconds > 0) window.setTimeout(refresh, seconds * 1000);
  }
  async function refresh() {
    try {
      const answer = await fetch(window.location.href, { credentials: "same-origin" });
      if (!answer.ok) throw new Error(String(answer.status));
      const page = new DOMParser().parseFromString(await answer.text(), "text/html");
      const fresh = page.getElementById("series-body");
      if (!fresh) return;
      body.replaceChildren(...fresh.childNodes);
      body.dataset.refresh = fresh.dataset.refresh;
      body.dataset.updated = new Date().toISOString();
      schedule(Number(fresh.dataset.refresh));
    } catch (error) {
      schedule(Number(body.dataset.refresh) * 2);
    }
  }
  schedule(Number(body.dataset.refresh));
})();

// The series archive: its reports render in the background the first time (the export
// answers 202 with its progress); the page shows how far, and downloads it once ready.
(function () {
  const link = document.getElementById("export-eln");
  const progress = document.getElementById("export-progress");
  if (!link || !progress) return;
  async function ask() {
    let answer;
    try {
      answer = await fetch(link.href, { method: "GET", credentials: "same-origin" });
    } catch (error) {
      progress.textContent = progress.dataset.failed;
      return;
    }
    if (answer.status === 202) {
      const state = await answer.json();
      progress.textContent = " " + progress.dataset.rendering
        .replace("{done}", String(state.reports_done))
        .replace("{total}", String(state.reports_total));
      const wait = Number(answer.headers.get("Retry-After")) || 2;
      window.setTimeout(ask, wait * 1000);
      return;
    }
    if (!answer.ok) {
      progress.textContent = " " + progress.dataset.failed;
      return;
    }
    progress.textContent = "";
    const file = URL.createObjectURL(await answer.blob());
    const save = document.createElement("a");
    save.href = file;
    save.download = link.href.split("/").slice(-2, -1)[0] + ".eln";
    document.body.appendChild(save);
    save.click();
    save.remove();
    window.setTimeout(() => URL.revokeObjectURL(file), 60000);
  }
  link.addEventListener("click", (event) => {
    event.preventDefault();
    ask();
  });
})();

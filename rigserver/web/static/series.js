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

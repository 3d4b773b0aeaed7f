// dynlab serve: add and remove entries of a repeated section; size the report's frame;
// keep the class page current. No framework, no build step.
"use strict";

function renumber(entries) {
  entries.querySelectorAll(":scope > fieldset.entry").forEach((e, k) => {
    e.querySelector("legend .n").textContent = k + 1;
  });
}

function addEntry(button) {
  const name = button.dataset.section;
  const entries = document.querySelector(`.entries[data-section="${name}"]`);
  const template = document.querySelector(`template[data-section="${name}"]`);
  const used = [...entries.querySelectorAll(":scope > fieldset.entry")].map(e => +e.dataset.index);
  const next = used.length ? Math.max(...used) + 1 : 0;
  const html = template.innerHTML.replaceAll("__i__", String(next));
  entries.insertAdjacentHTML("beforeend", html);
  renumber(entries);
  const added = entries.lastElementChild;
  const first = added.querySelector("input, select, textarea");
  if (first) first.focus();
}

document.addEventListener("click", event => {
  const target = event.target;
  if (target.matches("button.add")) addEntry(target);
  if (target.matches("button.remove")) {
    const entry = target.closest("fieldset.entry");
    const entries = entry.parentElement;
    if (entries.querySelectorAll(":scope > fieldset.entry").length > 1) entry.remove();
    else entry.querySelectorAll("input[type=text], textarea").forEach(i => { i.value = ""; });
    renumber(entries);
  }
});

function fitFrame(frame) {
  try {
    const doc = frame.contentDocument;
    if (doc && doc.body) frame.style.height = (doc.documentElement.scrollHeight + 20) + "px";
  } catch (e) { /* another origin: keep the default height */ }
}

document.querySelectorAll("iframe.report").forEach(frame => {
  frame.addEventListener("load", () => fitFrame(frame));
});

const handins = document.getElementById("handins");
if (handins) {
  let seen = null;
  const state = document.getElementById("state");
  async function poll() {
    try {
      const reply = await fetch(handins.dataset.status, {credentials: "same-origin"});
      const s = await reply.json();
      const body = handins.tBodies[0];
      body.replaceChildren(...s.handins.map(h => {
        const tr = document.createElement("tr");
        for (const v of [h.id, h.name, h.labs.join(", "), h.time]) {
          const td = document.createElement("td");
          td.textContent = v;
          tr.appendChild(td);
        }
        return tr;
      }));
      const files = document.getElementById("files");
      files.querySelectorAll("a").forEach(a => a.remove());
      for (const name of s.files) {
        const a = document.createElement("a");
        a.href = "/class/file/" + encodeURIComponent(name);
        a.textContent = name;
        files.append(a, " ");
      }
      state.textContent = s.state === "checking" ? state.dataset.checking : "";
      const key = s.checked + "/" + s.files.length;
      if (seen !== null && key !== seen) {
        document.getElementById("summary").src = "/class/file/summary.html?v=" + key;
      }
      seen = key;
    } catch (e) { /* the server restarting: try again */ }
    setTimeout(poll, 3000);
  }
  poll();
}

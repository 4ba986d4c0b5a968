// grove test trace: hands each picture its frame from the table (each tick's frames are stored
// once), marks the chosen step (the failing one first) in the list. No network.
(function () {
  "use strict";
  var errors = [];
  window.addEventListener("error", function (e) {
    errors.push(String(e.message));
    document.body.setAttribute("data-errors", errors.join(" | "));
  });
  var table = JSON.parse(document.getElementById("frames").textContent || "{}");
  Array.prototype.forEach.call(document.querySelectorAll("[data-frame]"), function (el) {
    var uri = table[el.getAttribute("data-frame")];
    if (!uri) { return; }
    if (el.tagName.toLowerCase() === "img") { el.setAttribute("src", uri); } else { el.setAttribute("href", uri); }
  });
  var links = document.querySelectorAll("nav.steps li");
  function mark(id) {
    Array.prototype.forEach.call(links, function (li) {
      var a = li.querySelector("a");
      li.classList.toggle("current", !!a && a.getAttribute("href") === "#" + id);
    });
  }
  window.addEventListener("hashchange", function () { mark(location.hash.slice(1)); });
  var failed = document.querySelector("section.failed");
  if (failed) { mark(failed.id); }
  document.body.setAttribute("data-ready", "1");
})();

// grove report: filtering and sorting of the trials, participants switched on and off on the
// task area (the heatmap is summed again over those shown). No network, no library.
(function () {
  "use strict";
  var errors = [];
  window.addEventListener("error", function (e) {
    errors.push(String(e.message));
    document.body.setAttribute("data-errors", errors.join(" | "));
  });

  function each(sel, f, root) { Array.prototype.forEach.call((root || document).querySelectorAll(sel), f); }

  // Filtering: the trials table and the trial sections follow the three selects.
  function filter() {
    var want = {};
    ["participant", "condition", "status"].forEach(function (k) {
      var s = document.getElementById("f-" + k);
      want[k] = s ? s.value : "";
    });
    var shown = 0;
    each("tr.trial-row, section.trial", function (el) {
      var ok = ["participant", "condition", "status"].every(function (k) {
        return !want[k] || el.getAttribute("data-" + k) === want[k];
      });
      el.classList.toggle("hidden", !ok);
      if (ok && el.tagName === "TR") { shown += 1; }
    });
    var c = document.getElementById("f-count");
    if (c) { c.textContent = " " + shown + " trials shown"; }
  }
  each(".filters select", function (s) { s.addEventListener("change", filter); });

  // Sorting: a click on a header sorts by that column, again to reverse.
  each("table.sortable", function (table) {
    each("th[data-sort]", function (th, i) {
      th.addEventListener("click", function () {
        var body = table.tBodies[0];
        var rows = Array.prototype.slice.call(body.rows);
        var dir = th.getAttribute("data-dir") === "asc" ? -1 : 1;
        th.setAttribute("data-dir", dir === 1 ? "asc" : "desc");
        var idx = Array.prototype.indexOf.call(th.parentNode.children, th);
        var num = th.getAttribute("data-sort") === "num";
        rows.sort(function (a, b) {
          var x = a.cells[idx].textContent.trim(), y = b.cells[idx].textContent.trim();
          if (num) {
            var fx = parseFloat(x), fy = parseFloat(y);
            fx = isNaN(fx) ? Infinity : fx; fy = isNaN(fy) ? Infinity : fy;
            return dir * (fx - fy);
          }
          return dir * x.localeCompare(y);
        });
        rows.forEach(function (r) { body.appendChild(r); });
      });
    });
  });

  // The task areas: participants on and off.
  var SVGNS = "http://www.w3.org/2000/svg";
  function redraw(id) {
    var svg = document.getElementById("area-" + id);
    var data = JSON.parse(document.getElementById("heat-" + id).textContent);
    var on = {};
    each('.switches[data-area="' + id + '"] input.pswitch', function (i) { on[i.getAttribute("data-p")] = i.checked; });
    each(".pp", function (el) { el.style.display = on[el.getAttribute("data-p")] ? "" : "none"; }, svg);
    var total = {}, max = 0;
    Object.keys(data.p).forEach(function (p) {
      if (!on[p]) { return; }
      data.p[p].forEach(function (c) {
        var k = c[0] + "," + c[1];
        total[k] = (total[k] || 0) + c[2];
        if (total[k] > max) { max = total[k]; }
      });
    });
    var g = svg.querySelector("g.heat");
    while (g.firstChild) { g.removeChild(g.firstChild); }
    g.setAttribute("data-max", max);
    Object.keys(total).forEach(function (k) {
      var xz = k.split(","), n = total[k];
      var r = document.createElementNS(SVGNS, "rect");
      r.setAttribute("x", (xz[0] * data.cell).toFixed(2));
      r.setAttribute("y", (xz[1] * data.cell).toFixed(2));
      r.setAttribute("width", data.cell);
      r.setAttribute("height", data.cell);
      r.setAttribute("data-n", n);
      r.setAttribute("fill", "#ff3b00");
      r.setAttribute("fill-opacity", (0.05 + 0.9 * Math.sqrt(n / max)).toFixed(3));
      g.appendChild(r);
    });
  }
  each(".switches", function (sw) {
    var id = sw.getAttribute("data-area");
    each("input.pswitch", function (i) { i.addEventListener("change", function () { redraw(id); }); }, sw);
    var set = function (v) { return function () { each("input.pswitch", function (i) { i.checked = v; }, sw); redraw(id); }; };
    sw.querySelector(".all-on").addEventListener("click", set(true));
    sw.querySelector(".all-off").addEventListener("click", set(false));
  });

  filter();
  document.body.setAttribute("data-ready", "1");
})();

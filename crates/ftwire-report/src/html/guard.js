// First script of an ftwire report: records the page's errors (uncaught exceptions, rejected
// promises, resources that fail to load, console.error) on <html data-errors>, for the browser
// test (`.ci/browser-test`), and still lets them reach the console.
(function () {
  var root = document.documentElement;
  var errors = [];
  var note = function (message) {
    errors.push(String(message));
    root.setAttribute("data-errors", errors.join(" | "));
  };
  root.setAttribute("data-errors", "");
  window.addEventListener("error", function (e) {
    var target = e.target && (e.target.src || e.target.href);
    note(e.message || (target ? "cannot load " + target : "error"));
  }, true);
  window.addEventListener("unhandledrejection", function (e) { note(e.reason); });
  var original = console.error;
  console.error = function () {
    note(Array.prototype.join.call(arguments, " "));
    return original.apply(console, arguments);
  };
})();

// fricctl's book: what sphinx-book-theme leaves to the page (issue 24).
//
// * Printing opens every collapsed block (the solutions, folded checks), so that paper holds
//   them; they close again after printing.
// * A figure of a chapter opens at full size in a new tab when clicked (the column scales
//   wide figures down).
window.addEventListener("beforeprint", () => {
  document.querySelectorAll("details:not([open])").forEach((d) => {
    d.dataset.fricctlClosed = "1";
    d.open = true;
  });
});
window.addEventListener("afterprint", () => {
  document.querySelectorAll("details[data-fricctl-closed]").forEach((d) => {
    d.open = false;
    delete d.dataset.fricctlClosed;
  });
});
document.addEventListener("DOMContentLoaded", () => {
  document.querySelectorAll("div.cell_output img, figure img").forEach((img) => {
    if (img.closest("a")) {
      return;  // already a link
    }
    img.classList.add("fricctl-zoom");
    if (!img.title) {
      img.title = "click to open the figure at full size";
    }
    img.addEventListener("click", () => window.open(img.src, "_blank", "noopener"));
  });
});

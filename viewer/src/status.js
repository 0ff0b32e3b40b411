// `window.viewerState`: a read-only snapshot of what the page shows, for
// tests and for a look from the browser's console. Each read builds a new
// frozen object; nothing written to it reaches the page.

/** @param {() => object} snapshot builds the current state */
export function exposeStatus(snapshot) {
  Object.defineProperty(window, 'viewerState', {
    get: () => Object.freeze(snapshot()),
    enumerable: true,
  });
}

// The page's one way to ask the API: JSON in and out, the API's refusal as an ApiError, and the
// latest request of a kind (a view, the plots of a selection) the only one whose answer is used.
// Every path is relative, so the page also works behind a reverse proxy at a sub-path.

// A refusal of the API: its error object ({code, field, message}) as `api`.
export class ApiError extends Error {
  constructor(error) {
    super(error.message);
    this.api = error;
  }
}

// The answer to GET `path`, or to POST of `body` as JSON when a body is given; throws ApiError
// when the API refuses.
export async function send(path, { body, signal } = {}) {
  const init = body === undefined ? { signal }
    : { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(body), signal };
  const res = await fetch(path, init);
  if (!res.ok) throw new ApiError((await res.json()).error);
  return res;
}

// send() for an answer in JSON. An answer that arrives after `signal` was aborted (the fetch was
// answered before the abort, or ignored it) is stale however complete: it throws the signal's
// AbortError instead, so the code that awaits it never acts on it.
export async function requestJson(path, options = {}) {
  const json = await (await send(path, options)).json();
  options.signal?.throwIfAborted();
  return json;
}

// The latest request of one kind. run() aborts the one before, so of two requests only the newer
// one's answers are acted on, whatever order they arrive in; an aborted request shows no error.
export class Latest {
  #controller = null;

  // Aborts the request under way, if any (its view is gone).
  cancel() {
    this.#controller?.abort();
  }

  // Runs work(signal) as the latest request of this kind; a failure of it while it is still the
  // latest goes to onError, a failure after a newer request aborted it (the AbortError of its
  // fetches or of send's check) is dropped.
  async run(work, onError) {
    this.cancel();
    const controller = new AbortController();
    this.#controller = controller;
    try {
      await work(controller.signal);
    } catch (e) {
      if (!controller.signal.aborted) onError(e);
    }
  }
}

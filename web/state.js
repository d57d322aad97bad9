// What the page shows, shared by its modules: the request of the plan view and its plans, the
// selected plan and its charts, the min-time answer and its charts, the measured series and the
// fluid catalogue.
export const state = {
  request: null, plans: {}, selected: null, charts: [],
  minTimeRequest: null, minTime: null, minTimeCharts: [],
  measured: null, plotContext: null, fluids: [],
};
window.sloshPage = state;  // for the browser test and the curious

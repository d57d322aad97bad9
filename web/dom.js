// What every part of the page does with the document: find an element, and tables whose rows
// select something.

export const $ = (id) => document.getElementById(id);

// A table body of one row per strategy: `rows` are {strategy, cells, title?, className?}; a row
// shows its cells as text and is selected by a click, or by Enter or Space when it has the focus
// (every row is focusable, so the table works with the keyboard), which calls
// onSelect(strategy).
export function fillSelectableRows(body, rows, onSelect) {
  body.replaceChildren();
  for (const row of rows) {
    const tr = document.createElement('tr');
    tr.dataset.strategy = row.strategy;
    tr.tabIndex = 0;
    if (row.title) tr.title = row.title;
    if (row.className) tr.classList.add(row.className);
    for (const text of row.cells) {
      const td = document.createElement('td');
      td.textContent = text;
      tr.appendChild(td);
    }
    tr.addEventListener('click', () => onSelect(row.strategy));
    tr.addEventListener('keydown', (e) => {
      if (e.key !== 'Enter' && e.key !== ' ') return;
      e.preventDefault();
      onSelect(row.strategy);
    });
    body.appendChild(tr);
  }
}

// Marks the row of `strategy` as the selected one of its body.
export function markSelectedRow(body, strategy) {
  for (const tr of body.querySelectorAll('tr')) tr.classList.toggle('selected', tr.dataset.strategy === strategy);
}

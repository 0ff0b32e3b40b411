// The 52 sliders, one per ARKit name, grouped as in Apple's order. A slider
// is disabled when no avatar has a morph target of its name.

import { ARKIT_COUNT, ARKIT_NAMES, GROUPS } from './arkit.js';

export class Sliders {
  /**
   * @param {HTMLElement} container
   * @param {(shape: number, value: number) => void} onInput a slider was moved
   */
  constructor(container, onInput) {
    this.inputs = [];
    this.outputs = [];
    for (const [title, first, end] of GROUPS) {
      const group = document.createElement('fieldset');
      const legend = document.createElement('legend');
      legend.textContent = title;
      group.append(legend);
      for (let shape = first; shape < end; shape++) group.append(this.row(shape, onInput));
      container.append(group);
    }
  }

  /** One labelled slider from 0 to 1 and its value. */
  row(shape, onInput) {
    const name = ARKIT_NAMES[shape];
    const label = document.createElement('label');
    label.className = 'slider';
    const text = document.createElement('span');
    text.textContent = name;
    const input = document.createElement('input');
    Object.assign(input, { type: 'range', min: '0', max: '1', step: '0.01', value: '0' });
    input.dataset.name = name;
    const output = document.createElement('output');
    output.textContent = '0.00';
    input.addEventListener('input', () => onInput(shape, Number(input.value)));
    label.append(text, input, output);
    this.inputs.push(input);
    this.outputs.push(output);
    return label;
  }

  /** Shows 52 weights (values outside [0, 1] are shown as numbers, the knob clamped). */
  show(weights) {
    for (let shape = 0; shape < ARKIT_COUNT; shape++) {
      this.inputs[shape].value = String(weights[shape]);
      this.outputs[shape].textContent = weights[shape].toFixed(2);
    }
  }

  /** Disables the sliders of names that no avatar has. */
  enable(present) {
    this.inputs.forEach((input, shape) => {
      input.disabled = !present[shape];
      input.title = present[shape] ? '' : 'no avatar has a morph target of this name';
    });
  }
}

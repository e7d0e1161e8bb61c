// The player's DOM: legend, error banner, and the control bar (play/pause, scrubbing slider, frame
// counter, speed, layout toggle, scene chooser). Knows nothing of three.js.

export const SPEEDS = [0.1, 0.25, 0.5, 1, 2];
export const LAYOUTS = { overlay: 'Overlaid', 'side-by-side': 'Side by side' };

function element(tag, attributes = {}, children = []) {
  const node = document.createElement(tag);
  for (const [key, value] of Object.entries(attributes)) {
    if (key === 'text') node.textContent = value;
    else node.setAttribute(key, value);
  }
  for (const child of children) node.append(child);
  return node;
}

export class Controls {
  // handlers: { onPlayToggle(), onSeek(frame), onSpeed(speed), onLayout(name), onFollow(on), onScene(index) }
  constructor(root, scenes, handlers) {
    this.handlers = handlers;
    this.viewport = element('div', { class: 'mv-viewport' });
    this.legend = element('ul', { class: 'mv-legend', 'aria-label': 'clips' });
    this.errors = element('div', { class: 'mv-errors', role: 'alert', hidden: '' });
    this.play = element('button', { class: 'mv-play', type: 'button', text: 'Play' });
    this.slider = element('input', { class: 'mv-slider', type: 'range', min: '0', max: '0', step: '1', value: '0',
      'aria-label': 'frame' });
    this.counter = element('span', { class: 'mv-frame-counter', 'data-frame': '0', text: 'frame 1 / 1' });
    this.speed = element('select', { class: 'mv-speed', 'aria-label': 'speed' },
      SPEEDS.map((s) => element('option', { value: String(s), text: `${s}×` })));
    this.layout = element('select', { class: 'mv-layout', 'aria-label': 'layout' },
      Object.entries(LAYOUTS).map(([value, text]) => element('option', { value, text })));
    this.follow = element('input', { type: 'checkbox', class: 'mv-follow' });
    const follow = element('label', { title: 'Keep the bodies in view as they travel' }, [this.follow, ' Follow']);
    const bar = element('div', { class: 'mv-bar' }, [this.play, this.slider, this.counter, this.speed, this.layout, follow]);
    if (scenes.length > 1) {
      this.scene = element('select', { class: 'mv-scene', 'aria-label': 'clip set' },
        scenes.map((s, i) => element('option', { value: String(i), text: s.label || `clip set ${i + 1}` })));
      this.scene.addEventListener('change', () => handlers.onScene(Number(this.scene.value)));
      bar.prepend(this.scene);
    }
    root.append(this.viewport, this.legend, this.errors, bar);
    this.play.addEventListener('click', () => handlers.onPlayToggle());
    this.slider.addEventListener('input', () => handlers.onSeek(Number(this.slider.value)));
    this.speed.addEventListener('change', () => handlers.onSpeed(Number(this.speed.value)));
    this.layout.addEventListener('change', () => handlers.onLayout(this.layout.value));
    this.follow.addEventListener('change', () => handlers.onFollow(this.follow.checked));
  }

  showClips(items) {  // [{ name, colour, note }]
    this.legend.replaceChildren(...items.map(({ name, colour, note }) => element('li', {}, [
      element('span', { class: 'mv-swatch', style: `background:${colour}` }), element('span', { text: name }),
      ...(note ? [element('span', { class: 'mv-note', text: note })] : []),
    ])));
  }

  showErrors(messages) {
    this.errors.replaceChildren(...messages.map((m) => element('p', { text: m })));
    this.errors.hidden = messages.length === 0;
  }

  setTimeline(frames) {
    this.slider.max = String(Math.max(0, frames - 1));
    this.frames = frames;
  }

  showFrame(frame, seconds) {
    this.slider.value = String(frame);
    this.counter.dataset.frame = String(frame);
    this.counter.textContent = `frame ${frame + 1} / ${this.frames} · ${seconds.toFixed(2)} s`;
  }

  showPlaying(playing) {
    this.play.textContent = playing ? 'Pause' : 'Play';
    this.play.setAttribute('aria-pressed', String(playing));
  }

  select(control, value) {
    if (this[control] && this[control].type === 'checkbox') this[control].checked = Boolean(value);
    else if (this[control]) this[control].value = String(value);
  }
}

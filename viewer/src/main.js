// Entry point of the bundle: reads the page's data (a JSON <script id="mocap-viewer-data">),
// starts the player in <div id="mocap-viewer">, and turns any failure into a readable message.
import css from './viewer.css';
import { Player } from './player.js';

function showFatal(root, message) {
  const box = document.createElement('div');
  box.className = 'mv-fatal';
  box.setAttribute('role', 'alert');
  const title = document.createElement('strong');
  title.textContent = 'This motion cannot be shown.';
  const detail = document.createElement('p');
  detail.textContent = message;
  box.append(title, detail);
  root.replaceChildren(box);
  root.dataset.state = 'error';
  document.body.dataset.viewerState = 'error';
}

// #layout=side-by-side&play=1&speed=0.5&scene=2&frame=40&follow=1 (or the same as a query string).
function urlOptions() {
  const params = new URLSearchParams(`${location.search.slice(1)}&${location.hash.slice(1)}`);
  const number = (key) => (params.has(key) ? Number(params.get(key)) : undefined);
  return { layout: params.get('layout') ?? undefined, play: params.get('play') === '1', speed: number('speed'),
    scene: number('scene'), frame: number('frame'), follow: params.has('follow') ? params.get('follow') === '1' : undefined };
}

function readData() {
  const node = document.getElementById('mocap-viewer-data');
  if (!node) throw new Error('the page carries no motion data');
  let data;
  try {
    data = JSON.parse(node.textContent);
  } catch (error) {
    throw new Error(`the page's motion data is not valid JSON (${error.message})`);
  }
  if (!Array.isArray(data.scenes) || data.scenes.length === 0 || !data.scenes.every((s) => Array.isArray(s.clips))) {
    throw new Error('the page carries no clips');
  }
  return data;
}

function start() {
  const style = document.createElement('style');
  style.textContent = css;
  document.head.append(style);
  const root = document.getElementById('mocap-viewer');
  if (!root) return;
  root.classList.add('mv-root');
  window.addEventListener('error', (event) => showFatal(root, event.message));
  try {
    new Player(root, readData(), urlOptions());
  } catch (error) {
    const webgl = /WebGL/i.test(String(error.message));
    showFatal(root, webgl ? `this browser could not start WebGL (${error.message})` : error.message);
  }
}

if (document.readyState === 'loading') document.addEventListener('DOMContentLoaded', start);
else start();

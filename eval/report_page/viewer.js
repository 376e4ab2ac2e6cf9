// report.html's comparison viewer: one render at a time, flipped or slid against the reference,
// its FLIP error map, its rays-per-pixel map or the aamap, zoomed to single pixels
// (nearest-neighbour) and panned; crops of its worst regions one click away. Reads the page's
// JSON (#aamap-viewer-data) and the images already on the page (#viewer-images); no network.
(function () {
  'use strict';
  const dataNode = document.getElementById('aamap-viewer-data');
  const root = document.getElementById('viewer');
  if (!dataNode || !root) return;
  const data = JSON.parse(dataNode.textContent);
  const W = data.width, H = data.height;
  if (!data.renders.length || !W || !H) return;

  const pictures = {};  // file name -> <img>
  document.querySelectorAll('#viewer-images img').forEach((img) => { pictures[img.getAttribute('src')] = img; });

  const el = (tag, props, children) => {
    const e = document.createElement(tag);
    Object.assign(e, props || {});
    (children || []).forEach((c) => e.append(c));
    return e;
  };
  const fmt = (v) => (v === null || v === undefined || !isFinite(v) ? '—' : String(Number(v.toPrecision(3))));

  // What each layer is, how to read it, and its colour bar.
  const t = data.flip_threshold;
  const LAYERS = {
    render: {label: 'render', file: (r) => r.layers.render,
      caption: (r) => `${r.name}: the render (sRGB at exposure ${fmt(data.exposure)}), ${fmt(r.mean_rpp)} primary rays per pixel on average.`},
    reference: {label: 'reference', file: () => data.reference,
      caption: () => `The reference: ${data.reference_text}.`},
    flip: {label: 'FLIP error', file: (r) => r.layers.flip,
      caption: (r) => `${r.name}: LDR-FLIP error per pixel against the reference. Black: indistinguishable; bright: clearly different. ` +
        `Pixels above the threshold ${fmt(t)} (dashed) are the "% FLIP" of Table 3 (${fmt(r.pct_flip)}% here).`,
      bar: {stops: data.colour_maps.magma, ticks: [[0, '0'], [0.25, '0.25'], [0.5, '0.5'], [0.75, '0.75'], [1, '1']], mark: t,
        unit: 'FLIP error (0 = identical, 1 = maximal perceived difference)'}},
    overlay: {label: 'error in red', file: (r) => r.layers.overlay,
      caption: (r) => `${r.name}: the render in grey with its FLIP error mixed in as red: half-strength red at the threshold ${fmt(t)}, ` +
        `full red at ${fmt(2 * t)} and above (the paper's Figure 8).`,
      bar: {stops: ['#808080', '#ff0000'], ticks: [[0, '0'], [0.5, fmt(t)], [1, '≥ ' + fmt(2 * t)]], unit: 'FLIP error'}},
    rpp: {label: 'rays/pixel', file: (r) => (r.uniform ? null : r.layers.rpp),
      caption: (r) => (r.uniform
        ? `${r.name}: uniform sampling, every pixel traced exactly ${r.rpp} primary rays (a constant map, not shown).`
        : `${r.name}: primary rays traced per pixel, ${fmt(r.mean_rpp)} on average. Black: 0 rays (the pixel was interpolated from its neighbours).`),
      bar: (r) => (r.rpp <= 1
        ? {stops: [['#000000', 0], ['#000000', 50], [data.colour_maps.viridis.slice(-1)[0], 50], [data.colour_maps.viridis.slice(-1)[0], 100]],
          ticks: [[0.25, '0'], [0.75, '1']], unit: 'primary rays per pixel (0: interpolated)'}
        : {stops: data.colour_maps.viridis, ticks: rppTicks(r.rpp), unit: 'primary rays per pixel (black = 0, interpolated)'})},
    aamap: {label: 'aamap', file: () => data.aamap,
      caption: () => 'The aamap from the Snapshot: black = smooth (the minimum of rays), brighter = more predicted aliasing (more rays). ' +
        'Selective strategies spend rays where it is above 0.',
      bar: {stops: ['#000000', '#ffffff'], ticks: [[0, '0'], [0.5, '0.5'], [1, '1']], unit: 'aamap value'}},
    causes: {label: 'causes', file: (r) => r.layers.causes,
      caption: (r) => `${r.name}: why pixels are still in error (bright, FLIP above ${fmt(t)}) or got more than one ray where ` +
        'one was enough (dark), coloured by what the tracer sees in the pixel (' +
        data.causes_legend.map(([name]) => name).join(', ') + '; the colours are in the legend of causes.png below). Black: neither.'},
  };
  const rppTicks = (max) => {
    if (max <= 1) return [[1, '1']];
    const ticks = [[0, '1'], [1, String(max)]];
    const mid = Math.round(Math.sqrt(max)) ** 2;
    if (mid > 1 && mid < max) ticks.splice(1, 0, [(mid - 1) / (max - 1), String(mid)]);
    return ticks;
  };

  const state = {index: data.initial || 0, a: 'render', b: 'reference', mode: 'flip', showB: false, split: 0.5,
    scale: 0, ox: 0, oy: 0};
  const render = () => data.renders[state.index];
  const fileOf = (layer) => LAYERS[layer].file(render());
  const available = (layer) => { const f = fileOf(layer); return !!(f && pictures[f]); };

  // ---- DOM -------------------------------------------------------------------------------------
  const box = Math.min(640, Math.max(320, window.innerWidth - 760));
  const cssW = W >= H ? box : Math.round(box * W / H), cssH = W >= H ? Math.round(box * H / W) : box;
  const dpr = window.devicePixelRatio || 1;
  const canvas = el('canvas', {width: Math.round(cssW * dpr), height: Math.round(cssH * dpr), tabIndex: 0,
    title: 'wheel: zoom at the cursor; drag: pan; Space: flip; 0: fit; 1-7: layer'});
  canvas.style.width = cssW + 'px';
  canvas.style.height = cssH + 'px';
  const ctx = canvas.getContext('2d');
  const readout = el('div', {className: 'v-readout'});
  const slider = el('input', {type: 'range', min: 0, max: 1000, value: 500, hidden: true});
  slider.style.width = cssW + 'px';
  const stage = el('div', {className: 'v-stage'}, [canvas, slider, readout]);

  const side = el('div', {className: 'v-side'});
  const picker = el('table', {className: 'v-picker'});
  const rowA = el('div', {className: 'v-row'}), rowB = el('div', {className: 'v-row'});
  const rowMode = el('div', {className: 'v-row'});
  const caption = el('p', {className: 'v-caption'});
  const cbar = el('div');
  const cropsTitle = el('h3', {textContent: 'Worst regions (largest summed FLIP error): click one to zoom there'});
  const crops = el('div', {className: 'v-crops'});
  side.append(picker, rowA, rowB, rowMode, caption, cbar, cropsTitle, crops);
  const mount = root.querySelector('.viewer') || root;
  mount.append(stage, side);

  // The render picker: Table 3's grid, rpp down, series across, % FLIP in each cell.
  const buttons = [];
  {
    const head = el('tr', {}, [el('th', {textContent: 'rpp'})]);
    data.series.forEach((s) => head.append(el('th', {textContent: s})));
    picker.append(head);
    data.rpps.forEach((rpp) => {
      const tr = el('tr', {}, [el('th', {textContent: String(rpp)})]);
      data.series.forEach((s) => {
        const td = el('td');
        data.renders.forEach((r, i) => {
          if (r.rpp !== rpp || r.series !== s) return;
          const b = el('button', {textContent: r.pct_flip === null ? r.name : fmt(r.pct_flip) + '%',
            title: `${r.name}: ${fmt(r.mean_rpp)} rays/pixel, ${fmt(r.pct_flip)}% pixels above FLIP ${fmt(t)}`});
          b.dataset.render = r.name;
          b.addEventListener('click', () => select(i));
          buttons[i] = b;
          td.append(b);
        });
        tr.append(td);
      });
      picker.append(tr);
    });
    const note = el('caption', {textContent: 'Pick a render (cells: % FLIP error pixels)'});
    note.style.cssText = 'caption-side:top;text-align:left;font-size:12px;color:#555';
    picker.prepend(note);
  }

  const layerButtons = {a: {}, b: {}};
  const buildLayerRow = (row, slot, label) => {
    row.append(el('span', {className: 'v-label', textContent: label}));
    Object.keys(LAYERS).forEach((layer, k) => {
      const b = el('button', {textContent: LAYERS[layer].label, title: slot === 'a' ? `key ${k + 1}` : ''});
      b.dataset.layer = layer;
      b.addEventListener('click', () => setLayer(slot, layer));
      layerButtons[slot][layer] = b;
      row.append(b);
    });
  };
  buildLayerRow(rowA, 'a', 'show');
  buildLayerRow(rowB, 'b', 'against');
  const modeButtons = {
    flip: el('button', {textContent: 'flip (Space)', title: 'show the other image while toggled'}),
    slide: el('button', {textContent: 'slider', title: 'left of the line: "show"; right: "against"'}),
  };
  const zoomButtons = [['fit', 0], ['1:1', 1], ['4×', 4], ['16×', 16]].map(([label, s]) => {
    const b = el('button', {textContent: label});
    b.addEventListener('click', () => zoomTo(s));
    return b;
  });
  modeButtons.flip.addEventListener('click', () => { if (state.mode === 'flip') state.showB = !state.showB; setMode('flip'); });
  modeButtons.slide.addEventListener('click', () => setMode('slide'));
  rowMode.append(el('span', {className: 'v-label', textContent: 'compare'}), modeButtons.flip, modeButtons.slide,
    el('span', {className: 'v-label', textContent: '  zoom'}), ...zoomButtons);

  // ---- drawing ---------------------------------------------------------------------------------
  const fitScale = () => Math.min(canvas.width / W, canvas.height / H);
  const drawLayer = (c, layer, sx, sy, sw, sh, dx, dy, dw, dh) => {
    const f = fileOf(layer), img = f && pictures[f];
    if (!img || !img.complete || !img.naturalWidth) return false;
    // Every layer is mapped onto the render's W x H pixels: the rays-per-pixel PNG carries its
    // legend below the image, and a map of another resolution still lines up.
    const kx = layer === 'rpp' ? 1 : img.naturalWidth / W, ky = layer === 'rpp' ? 1 : img.naturalHeight / H;
    c.drawImage(img, sx * kx, sy * ky, sw * kx, sh * ky, dx, dy, dw, dh);
    return true;
  };
  const drawView = (layer, clipX) => {
    // The visible part of the image, in image pixels, drawn with integer-aligned pixel edges.
    const s = state.scale;
    const x0 = Math.max(0, Math.floor(-state.ox / s)), y0 = Math.max(0, Math.floor(-state.oy / s));
    const x1 = Math.min(W, Math.ceil((canvas.width - state.ox) / s)), y1 = Math.min(H, Math.ceil((canvas.height - state.oy) / s));
    if (x1 <= x0 || y1 <= y0) return;
    ctx.save();
    if (clipX !== undefined) { ctx.beginPath(); ctx.rect(clipX, 0, canvas.width - clipX, canvas.height); ctx.clip(); }
    const ok = drawLayer(ctx, layer, x0, y0, x1 - x0, y1 - y0, state.ox + x0 * s, state.oy + y0 * s, (x1 - x0) * s, (y1 - y0) * s);
    ctx.restore();
    return ok;
  };
  const draw = () => {
    ctx.imageSmoothingEnabled = false;
    ctx.fillStyle = '#222';
    ctx.fillRect(0, 0, canvas.width, canvas.height);
    if (state.mode === 'slide') {
      const x = Math.round(state.split * canvas.width);
      drawView(state.a);
      ctx.fillStyle = '#222';
      ctx.fillRect(x, 0, canvas.width - x, canvas.height);
      drawView(state.b, x);
      ctx.fillStyle = '#fff';
      ctx.fillRect(x - 1, 0, 2, canvas.height);
    } else {
      drawView(state.showB ? state.b : state.a);
    }
    root.dataset.shown = state.mode === 'slide' ? `${state.a}|${state.b}` : (state.showB ? state.b : state.a);
    root.dataset.render = render().name;
    root.dataset.scale = String(state.scale / dpr);
  };

  const colourBar = (bar) => {
    const d = el('div', {className: 'cbar'});
    const n = bar.stops.length;
    d.append(el('div', {className: 'bar'}));
    // A stop is a colour (evenly spaced) or [colour, percent] (hard steps).
    const stop = (c, i) => (Array.isArray(c) ? `${c[0]} ${c[1]}%` : `${c} ${(100 * i / Math.max(1, n - 1)).toFixed(1)}%`);
    d.firstChild.style.background = `linear-gradient(to right, ${bar.stops.map(stop).join(', ')})`;
    bar.ticks.forEach(([p, label]) => { const tk = el('span', {className: 'tick', textContent: label}); tk.style.left = (100 * p) + '%'; d.append(tk); });
    if (bar.mark !== undefined) { const m = el('span', {className: 'mark', title: `threshold ${fmt(bar.mark)}`}); m.style.left = (100 * bar.mark) + '%'; d.append(m); }
    d.append(el('span', {className: 'unit', textContent: bar.unit}));
    return d;
  };

  const describe = () => {
    const r = render();
    const shown = state.mode === 'slide' ? [state.a, state.b] : [state.showB ? state.b : state.a];
    caption.textContent = shown.map((l) => LAYERS[l].caption(r)).join(' | Right of the line: ');
    if (state.mode === 'slide') caption.textContent = 'Left of the line: ' + caption.textContent;
    if (r.uniform) caption.textContent += ' ' + LAYERS.rpp.caption(r).replace(`${r.name}: u`, 'U');
    cbar.replaceChildren(...shown.filter((l) => LAYERS[l].bar).map((l) => {
      const b = LAYERS[l].bar;
      return colourBar(typeof b === 'function' ? b(r) : b);
    }));
  };

  const updateControls = () => {
    buttons.forEach((b, i) => b && b.setAttribute('aria-pressed', String(i === state.index)));
    ['a', 'b'].forEach((slot) => Object.entries(layerButtons[slot]).forEach(([layer, b]) => {
      b.setAttribute('aria-pressed', String(state[slot] === layer));
      b.disabled = !available(layer);
      if (layer === 'rpp' && render().uniform) b.title = `uniform: every pixel ${render().rpp} rays`;
    }));
    modeButtons.flip.setAttribute('aria-pressed', String(state.mode === 'flip'));
    modeButtons.flip.textContent = state.mode === 'flip' && state.showB ? 'flip back (Space)' : 'flip (Space)';
    modeButtons.slide.setAttribute('aria-pressed', String(state.mode === 'slide'));
    slider.hidden = state.mode !== 'slide';
  };

  // Crops of the worst regions: the "show" layer beside the "against" layer, 4 px per pixel or so.
  const drawCrops = () => {
    const r = render();
    crops.replaceChildren();
    cropsTitle.hidden = !r.regions.length;
    r.regions.forEach((g, k) => {
      const side = Math.max(64, Math.min(120, g.size * 3));
      const c = el('canvas', {width: 2 * side + 4, height: side});
      const cc = c.getContext('2d');
      cc.imageSmoothingEnabled = false;
      cc.fillStyle = '#fff';
      cc.fillRect(0, 0, c.width, c.height);
      drawLayer(cc, state.a, g.x, g.y, g.size, g.size, 0, 0, side, side);
      drawLayer(cc, state.b, g.x, g.y, g.size, g.size, side + 4, 0, side, side);
      const card = el('div', {className: 'v-crop', title: 'zoom the viewer onto this region'},
        [c, el('div', {textContent: `${k + 1}. mean FLIP ${fmt(g.flip_mean)}, x ${g.x}–${g.x + g.size - 1}, y ${g.y}–${g.y + g.size - 1}`}),
          el('div', {textContent: `left: ${LAYERS[state.a].label}, right: ${LAYERS[state.b].label}`})]);
      card.dataset.region = String(k);
      card.addEventListener('click', () => zoomToRegion(g));
      crops.append(card);
    });
  };

  const refresh = () => { updateControls(); describe(); draw(); drawCrops(); };

  // ---- actions ---------------------------------------------------------------------------------
  const clampView = () => {
    const s = state.scale;
    const cw = canvas.width, ch = canvas.height;
    state.ox = W * s <= cw ? (cw - W * s) / 2 : Math.min(0, Math.max(cw - W * s, state.ox));
    state.oy = H * s <= ch ? (ch - H * s) / 2 : Math.min(0, Math.max(ch - H * s, state.oy));
    // Whole device pixels: pixel edges stay sharp at any zoom.
    state.ox = Math.round(state.ox);
    state.oy = Math.round(state.oy);
  };
  // Zoom by screen pixels per image pixel (CSS pixels; 0: fit), keeping the point (px, py) of
  // the canvas (device pixels) fixed.
  const zoomAt = (s, px, py) => {
    const next = Math.max(fitScale() / 2, Math.min(64 * dpr, s));
    const ix = (px - state.ox) / state.scale, iy = (py - state.oy) / state.scale;
    state.scale = next;
    state.ox = px - ix * next;
    state.oy = py - iy * next;
    clampView();
    draw();
  };
  const zoomTo = (s) => {
    if (!s) { state.scale = fitScale(); state.ox = 0; state.oy = 0; clampView(); draw(); return; }
    zoomAt(s * dpr, canvas.width / 2, canvas.height / 2);
  };
  const zoomToRegion = (g) => {
    state.scale = Math.min(canvas.width, canvas.height) / (g.size * 1.25);
    state.ox = canvas.width / 2 - (g.x + g.size / 2) * state.scale;
    state.oy = canvas.height / 2 - (g.y + g.size / 2) * state.scale;
    clampView();
    draw();
  };
  const select = (i) => {
    state.index = i;
    if (!available(state.a)) state.a = 'render';
    if (!available(state.b)) state.b = available('reference') ? 'reference' : 'render';
    refresh();
  };
  const setLayer = (slot, layer) => {
    if (!available(layer)) return;
    state[slot] = layer;
    if (slot === 'a') state.showB = false;
    refresh();
  };
  const setMode = (mode) => {
    state.mode = mode;
    if (mode === 'slide') state.showB = false;
    refresh();
  };

  // ---- input -----------------------------------------------------------------------------------
  const toCanvas = (e) => { const b = canvas.getBoundingClientRect(); return [(e.clientX - b.left) * dpr, (e.clientY - b.top) * dpr]; };
  canvas.addEventListener('wheel', (e) => {
    e.preventDefault();
    const [px, py] = toCanvas(e);
    zoomAt(state.scale * (e.deltaY < 0 ? 1.25 : 0.8), px, py);
  }, {passive: false});
  let drag = null;
  canvas.addEventListener('pointerdown', (e) => {
    const [px, py] = toCanvas(e);
    const onDivider = state.mode === 'slide' && Math.abs(px - state.split * canvas.width) < 8 * dpr;
    drag = {px, py, ox: state.ox, oy: state.oy, divider: onDivider};
    canvas.setPointerCapture(e.pointerId);
    canvas.style.cursor = 'grabbing';
  });
  canvas.addEventListener('pointermove', (e) => {
    const [px, py] = toCanvas(e);
    const ix = Math.floor((px - state.ox) / state.scale), iy = Math.floor((py - state.oy) / state.scale);
    readout.textContent = ix >= 0 && iy >= 0 && ix < W && iy < H
      ? `pixel (${ix}, ${iy})   zoom ${fmt(state.scale / dpr)}×` : `zoom ${fmt(state.scale / dpr)}×`;
    if (!drag) return;
    if (drag.divider) {
      state.split = Math.max(0, Math.min(1, px / canvas.width));
      slider.value = String(Math.round(state.split * 1000));
    } else {
      state.ox = drag.ox + px - drag.px;
      state.oy = drag.oy + py - drag.py;
      clampView();
    }
    draw();
  });
  const endDrag = () => { drag = null; canvas.style.cursor = ''; };
  canvas.addEventListener('pointerup', endDrag);
  canvas.addEventListener('pointercancel', endDrag);
  canvas.addEventListener('dblclick', () => zoomTo(state.scale > fitScale() * 1.01 ? 0 : 4));
  slider.addEventListener('input', () => { state.split = Number(slider.value) / 1000; draw(); });
  canvas.addEventListener('keydown', (e) => {
    const layers = Object.keys(LAYERS);
    if (e.key === ' ' || e.key === 'f') { state.mode = 'flip'; state.showB = !state.showB; refresh(); }
    else if (e.key === '0') zoomTo(0);
    else if (e.key === '+' || e.key === '=') zoomAt(state.scale * 1.25, canvas.width / 2, canvas.height / 2);
    else if (e.key === '-') zoomAt(state.scale * 0.8, canvas.width / 2, canvas.height / 2);
    else if (e.key >= '1' && e.key <= String(layers.length)) setLayer('a', layers[Number(e.key) - 1]);
    else return;
    e.preventDefault();
  });
  // Images still loading draw when they arrive.
  Object.values(pictures).forEach((img) => { if (!img.complete) img.addEventListener('load', () => { draw(); drawCrops(); }); });

  // For scripts and tests: the same actions the buttons take, and what is shown.
  window.aamapViewer = {
    renders: () => data.renders.map((r) => r.name),
    select: (name) => { const i = data.renders.findIndex((r) => r.name === name); if (i >= 0) select(i); return i >= 0; },
    show: (layer) => setLayer('a', layer),
    against: (layer) => setLayer('b', layer),
    flip: () => { state.mode = 'flip'; state.showB = !state.showB; refresh(); },
    slide: (split) => { if (split !== undefined) state.split = split; setMode('slide'); },
    zoom: (s, x, y) => (x === undefined ? zoomTo(s) : zoomAt(s * dpr, state.ox + x * state.scale, state.oy + y * state.scale)),
    zoomToRegion: (k) => { const g = render().regions[k]; if (g) zoomToRegion(g); return !!g; },
    state: () => ({render: render().name, shown: root.dataset.shown, mode: state.mode, scale: state.scale / dpr,
      offset: [state.ox / dpr, state.oy / dpr], dpr}),
    canvas,
  };

  zoomTo(0);
  refresh();
})();

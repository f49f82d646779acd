// The review page's behaviour: the film strip, the slider and keys that step frames, the pose,
// the three CT slices through the camera with the view direction, and the optional coverage
// and measurement sections. Data: window.REVIEW (review_data.js) and window.REVIEW_VOLUME
// (review_volume.js, null without a CT), both written by cvc.
(function () {
  'use strict';

  var problems = [];
  function report(message) {
    problems.push(message);
    var box = document.getElementById('problems');
    box.textContent = problems.join(' ');
    box.hidden = false;
    console.error('review page: ' + message);
  }

  function element(tag, attributes, text) {
    var node = document.createElement(tag);
    Object.keys(attributes || {}).forEach(function (key) { node.setAttribute(key, attributes[key]); });
    if (text !== undefined) node.textContent = text;
    return node;
  }

  // A relative file path as a URL: each segment escaped, so '#', '?' or '%' in a name load the file.
  function fileUrl(path) { return path.split('/').map(encodeURIComponent).join('/'); }

  function fixed(value, digits) { return Number(value).toFixed(digits); }
  function vectorText(v, digits) { return '(' + v.map(function (x) { return fixed(x, digits); }).join(', ') + ')'; }
  function thousands(value) { return Math.round(value).toLocaleString('en-US').replace(/,/g, '\u2009'); }

  var data = window.REVIEW;
  if (!data || !Array.isArray(data.frames)) {
    report('review_data.js is missing or broken: there is nothing to show.');
    document.getElementById('viewer').hidden = true;
    document.getElementById('context').hidden = true;
    document.getElementById('images').hidden = true;
    document.body.setAttribute('data-ready', '1');
    return;
  }
  var volume = window.REVIEW_VOLUME;
  if (volume === undefined) report('review_volume.js is missing: the CT slices cannot be drawn.');

  var frames = data.frames;
  var current = 0;
  var positionOfFrameIndex = {};
  frames.forEach(function (frame, position) { positionOfFrameIndex[frame.index] = position; });

  document.title = data.title || document.title;
  document.getElementById('title').textContent = data.title || 'cvc review';
  var facts = document.getElementById('facts');
  (data.facts || []).forEach(function (fact) {
    var row = element('div');
    row.appendChild(element('dt', {}, fact.label));
    row.appendChild(element('dd', { title: fact.value }, fact.value));
    facts.appendChild(row);
  });

  // ---- frames: large view, slider, strip, images -------------------------------------------

  var slider = document.getElementById('slider');
  var large = document.getElementById('large');
  var largeLink = document.getElementById('large-link');
  var strip = document.getElementById('strip');
  var thumbnails = [];

  function largeImageOf(frame) {
    if (frame.sheet) return { path: frame.sheet, caption: data.sheet_caption || 'review sheet' };
    if (frame.images.length) return { path: frame.images[0].path, caption: frame.images[0].label };
    return null;
  }

  function buildStrip() {
    var unseenFrames = {};
    if (data.coverage) {
      (data.coverage.patches || []).forEach(function (patch) { unseenFrames[patch.nearest_frame] = true; });
    }
    frames.forEach(function (frame, position) {
      var figure = element('figure', { title: 'frame ' + frame.index });
      var shown = largeImageOf(frame);
      var image = element('img', { alt: 'frame ' + frame.index, loading: 'lazy' });
      if (shown) image.src = fileUrl(shown.path);
      figure.appendChild(image);
      figure.appendChild(element('figcaption', {}, String(frame.index)));
      if (unseenFrames[frame.index]) figure.appendChild(element('span', { class: 'unseen-mark', title: 'an unseen patch is nearest to this frame' }));
      figure.addEventListener('click', function () { show(position); });
      strip.appendChild(figure);
      thumbnails.push(figure);
    });
  }

  function showImages(frame) {
    var groups = document.getElementById('image-groups');
    groups.textContent = '';
    var byGroup = {};
    var order = [];
    frame.images.forEach(function (image) {
      var name = image.group || '';
      if (!(name in byGroup)) { byGroup[name] = []; order.push(name); }
      byGroup[name].push(image);
    });
    order.forEach(function (name) {
      var row = element('div', { class: 'group' });
      if (name) row.appendChild(element('p', { class: 'group-name' }, name));
      byGroup[name].forEach(function (image) {
        var figure = element('figure');
        var link = element('a', { href: fileUrl(image.path), target: '_blank', rel: 'noopener' });
        var img = element('img', { alt: image.label, 'data-path': image.path });
        // A wide picture (a before/after sheet) gets more height, to show as much as a wall.
        img.addEventListener('load', function () { img.classList.toggle('wide', img.naturalWidth > 2.5 * img.naturalHeight); });
        img.src = fileUrl(image.path);
        link.appendChild(img);
        figure.appendChild(link);
        figure.appendChild(element('figcaption', {}, image.label));
        row.appendChild(figure);
      });
      groups.appendChild(row);
    });
    document.getElementById('images').hidden = frame.images.length === 0;
  }

  // Patient direction of a unit vector in LPS, as letters: (0.1, -0.9, 0.4) -> "A 0.90, S 0.40, L 0.10".
  function patientDirectionText(lps) {
    var letters = [['R', 'L'], ['A', 'P'], ['I', 'S']];
    return lps.map(function (value, axis) { return { letter: letters[axis][value < 0 ? 0 : 1], size: Math.abs(value) }; })
      .sort(function (a, b) { return b.size - a.size; })
      .filter(function (part) { return part.size >= 0.05; })
      .map(function (part) { return part.letter + '\u00a0' + fixed(part.size, 2); }).join(', ');
  }

  function showPose(frame, position) {
    var table = document.getElementById('pose');
    table.textContent = '';
    function row(label, value) {
      var tr = element('tr');
      tr.appendChild(element('th', {}, label));
      tr.appendChild(element('td', {}, value));
      table.appendChild(tr);
    }
    row('frame', (position + 1) + ' of ' + frames.length + '  (frame_' + String(frame.index).padStart(4, '0') + ')');
    row('along the path', fixed(frame.arc_mm, 1) + ' mm of ' + fixed(data.path_length_mm, 1) + ' mm');
    row('position', vectorText(frame.pose.position_mm, 1) + ' mm');
    row('forward', vectorText(frame.pose.forward, 3));
    row('up', vectorText(frame.pose.up, 3));
    if (frame.patient_lps_mm) row('patient (LPS)', vectorText(frame.patient_lps_mm, 1) + ' mm');
    if (volume && volume.direction_lps) {
      row('looking toward', patientDirectionText(lpsOf(frame.pose.forward)));
    }
    if (data.coverage && data.coverage.cumulative_percent && position < data.coverage.cumulative_percent.length) {
      row('wall seen so far', fixed(data.coverage.cumulative_percent[position], 1) + ' %');
    }
  }

  function show(position) {
    if (!frames.length) return;
    current = Math.max(0, Math.min(frames.length - 1, position));
    var frame = frames[current];
    slider.value = String(current);
    var shown = largeImageOf(frame);
    if (shown) {
      large.src = fileUrl(shown.path);
      largeLink.href = fileUrl(shown.path);
    } else {
      large.removeAttribute('src');
      largeLink.removeAttribute('href');
    }
    document.getElementById('large-caption').textContent = shown ? shown.caption : 'this frame has no images';
    document.getElementById('frame-label').textContent =
      'frame ' + (current + 1) + ' of ' + frames.length + ' \u00b7 ' + fixed(frame.arc_mm, 1) + ' mm along the path';
    thumbnails.forEach(function (figure, i) { figure.classList.toggle('current', i === current); });
    // The strip scrolls to the current thumbnail; the page itself stays where the reader has it.
    var box = strip.getBoundingClientRect(), thumb = thumbnails[current].getBoundingClientRect();
    if (thumb.left < box.left) strip.scrollLeft += thumb.left - box.left;
    else if (thumb.right > box.right) strip.scrollLeft += thumb.right - box.right;
    showImages(frame);
    showPose(frame, current);
    drawSlices(frame);
    markCoverage();
    markCandidates();
    try { history.replaceState(null, '', '#frame=' + frame.index); } catch (ignored) { /* some browsers refuse it for files */ }
  }

  // ---- CT slices --------------------------------------------------------------------------

  var grey = null;
  var sliceViews = [];
  var kSliceBoxPx = 300;

  function lpsOf(v) {
    var d = volume.direction_lps;  // columns: grid axes in LPS
    return [0, 1, 2].map(function (p) { return d[0][p] * v[0] + d[1][p] * v[1] + d[2][p] * v[2]; });
  }

  function decodeVolume() {
    var text = atob(volume.grey_base64);
    grey = new Uint8Array(text.length);
    for (var i = 0; i < text.length; ++i) grey[i] = text.charCodeAt(i);
    var dims = volume.dims;
    if (grey.length !== dims[0] * dims[1] * dims[2]) throw new Error('review_volume.js holds ' + grey.length + ' voxels, not ' + dims.join('\u00d7'));
  }

  function buildSlices() {
    var container = document.getElementById('slices');
    volume.views.forEach(function (view) {
      var columns = volume.dims[view.column_axis], rows = volume.dims[view.row_axis];
      var widthMm = columns * volume.spacing_mm[view.column_axis];
      var heightMm = rows * volume.spacing_mm[view.row_axis];
      var pxPerMm = Math.min(kSliceBoxPx / widthMm, kSliceBoxPx / heightMm);
      var ratio = window.devicePixelRatio || 1;
      var canvas = element('canvas', { 'data-view': view.name });
      canvas.style.width = Math.round(widthMm * pxPerMm) + 'px';
      canvas.style.height = Math.round(heightMm * pxPerMm) + 'px';
      canvas.width = Math.round(widthMm * pxPerMm * ratio);
      canvas.height = Math.round(heightMm * pxPerMm * ratio);
      var source = element('canvas');
      source.width = columns;
      source.height = rows;
      var figure = element('figure');
      var caption = element('figcaption');
      figure.appendChild(canvas);
      figure.appendChild(caption);
      container.appendChild(figure);
      sliceViews.push({ view: view, canvas: canvas, source: source, caption: caption, columns: columns, rows: rows,
        widthMm: widthMm, heightMm: heightMm, scale: pxPerMm * ratio, ratio: ratio });
    });
    var note = 'W ' + volume.window.width_hu + ' / L ' + volume.window.level_hu + ' HU, reduced to ' +
      volume.dims.join('\u00d7') + ' voxels of ' + volume.spacing_mm.map(function (s) { return fixed(s, 2); }).join('\u00d7') +
      ' mm (box filter). Radiological convention: the patient\u2019s right on the image\u2019s left; sagittal seen from the left.';
    if (volume.oblique) note += ' The scan is oblique: the labels name the nearest patient direction.';
    note += ' Yellow: the camera and its view direction; blue: the path.';
    document.getElementById('slices-note').textContent = note;
  }

  // Continuous reduced-grid index of a point in volume mm.
  function gridIndexOf(pointMm, axis) { return (pointMm[axis] - volume.offset_mm[axis]) / volume.spacing_mm[axis]; }

  // Canvas pixel of a point in volume mm on a view (the point's own slice position ignored).
  function canvasPointOf(slice, pointMm) {
    var view = slice.view;
    var u = gridIndexOf(pointMm, view.column_axis), v = gridIndexOf(pointMm, view.row_axis);
    if (view.column_flipped) u = slice.columns - 1 - u;
    if (view.row_flipped) v = slice.rows - 1 - v;
    return [(u + 0.5) * volume.spacing_mm[view.column_axis] * slice.scale,
            (v + 0.5) * volume.spacing_mm[view.row_axis] * slice.scale];
  }

  // Canvas direction (per mm) of a vector in volume axes, projected onto the view.
  function canvasDirectionOf(slice, vector) {
    var view = slice.view;
    return [vector[view.column_axis] * (view.column_flipped ? -1 : 1) * slice.scale,
            vector[view.row_axis] * (view.row_flipped ? -1 : 1) * slice.scale];
  }

  function drawSliceImage(slice, sliceIndex) {
    var view = slice.view, dims = volume.dims;
    var strides = [1, dims[0], dims[0] * dims[1]];
    var pixels = new ImageData(slice.columns, slice.rows);
    var base = sliceIndex * strides[view.normal_axis];
    for (var r = 0; r < slice.rows; ++r) {
      var gridRow = view.row_flipped ? slice.rows - 1 - r : r;
      for (var c = 0; c < slice.columns; ++c) {
        var gridColumn = view.column_flipped ? slice.columns - 1 - c : c;
        var value = grey[base + gridColumn * strides[view.column_axis] + gridRow * strides[view.row_axis]];
        var o = 4 * (r * slice.columns + c);
        pixels.data[o] = pixels.data[o + 1] = pixels.data[o + 2] = value;
        pixels.data[o + 3] = 255;
      }
    }
    slice.source.getContext('2d').putImageData(pixels, 0, 0);
    var context = slice.canvas.getContext('2d');
    context.imageSmoothingEnabled = true;
    context.imageSmoothingQuality = 'high';
    context.drawImage(slice.source, 0, 0, slice.canvas.width, slice.canvas.height);
    return context;
  }

  function drawArrow(context, from, to, width) {
    var dx = to[0] - from[0], dy = to[1] - from[1], length = Math.hypot(dx, dy);
    context.lineWidth = width;
    context.beginPath();
    context.moveTo(from[0], from[1]);
    context.lineTo(to[0], to[1]);
    context.stroke();
    if (length < 1) return;
    var ux = dx / length, uy = dy / length, head = Math.min(4 * width + 4, 0.5 * length + 3);
    context.beginPath();
    context.moveTo(to[0], to[1]);
    context.lineTo(to[0] - head * (ux - 0.5 * uy), to[1] - head * (uy + 0.5 * ux));
    context.lineTo(to[0] - head * (ux + 0.5 * uy), to[1] - head * (uy - 0.5 * ux));
    context.closePath();
    context.fill();
  }

  function drawLabels(context, slice) {
    var labels = slice.view.labels, w = slice.canvas.width, h = slice.canvas.height, ratio = slice.ratio;
    context.font = '600 ' + Math.round(13 * ratio) + 'px system-ui, sans-serif';
    context.fillStyle = 'rgba(255, 255, 255, 0.85)';
    context.shadowColor = '#000';
    context.shadowBlur = 3 * ratio;
    var pad = 5 * ratio;
    context.textBaseline = 'middle';
    context.textAlign = 'left'; context.fillText(labels.left, pad, h / 2);
    context.textAlign = 'right'; context.fillText(labels.right, w - pad, h / 2);
    context.textAlign = 'center'; context.textBaseline = 'top'; context.fillText(labels.top, w / 2, pad);
    context.textBaseline = 'bottom'; context.fillText(labels.bottom, w / 2, h - pad);
    context.textAlign = 'left'; context.textBaseline = 'top';
    context.font = Math.round(11 * ratio) + 'px system-ui, sans-serif';
    context.fillStyle = 'rgba(255, 255, 255, 0.65)';
    context.fillText(slice.view.name, pad, pad);
    context.shadowBlur = 0;
  }

  function drawSlices(frame) {
    if (!grey) return;
    var position = frame.pose.position_mm, forward = frame.pose.forward;
    sliceViews.forEach(function (slice) {
      var view = slice.view, n = volume.dims[view.normal_axis];
      var exact = gridIndexOf(position, view.normal_axis);
      var sliceIndex = Math.max(0, Math.min(n - 1, Math.round(exact)));
      var context = drawSliceImage(slice, sliceIndex);
      var ratio = slice.ratio;

      // The path, faint, projected onto the slice.
      context.strokeStyle = 'rgba(79, 195, 247, 0.55)';
      context.lineWidth = 1.5 * ratio;
      context.beginPath();
      frames.forEach(function (other, i) {
        var p = canvasPointOf(slice, other.pose.position_mm);
        if (i === 0) context.moveTo(p[0], p[1]); else context.lineTo(p[0], p[1]);
      });
      context.stroke();

      // The camera and its view direction: an arrow a sixth of the slice long when forward lies in
      // the slice, shorter as it leaves it.
      var at = canvasPointOf(slice, position);
      var d = canvasDirectionOf(slice, forward);
      var lengthMm = Math.max(slice.widthMm, slice.heightMm) / 6;
      context.strokeStyle = context.fillStyle = '#ffd54f';
      context.shadowColor = 'rgba(0, 0, 0, 0.8)';
      context.shadowBlur = 2 * ratio;
      drawArrow(context, at, [at[0] + d[0] * lengthMm, at[1] + d[1] * lengthMm], 2 * ratio);
      context.beginPath();
      context.arc(at[0], at[1], 3.5 * ratio, 0, 2 * Math.PI);
      context.fill();
      context.shadowBlur = 0;
      drawLabels(context, slice);

      var inside = Math.abs(exact - sliceIndex) <= 0.5 ? '' : ' (camera outside the volume)';
      slice.caption.textContent = view.name + ' ' + (sliceIndex + 1) + ' / ' + n + ' at ' +
        fixed(volume.offset_mm[view.normal_axis] + sliceIndex * volume.spacing_mm[view.normal_axis], 1) + ' mm' + inside;
    });
  }

  // ---- coverage ---------------------------------------------------------------------------

  var curve = null;

  function buildCoverage() {
    var coverage = data.coverage;
    if (!coverage) return;
    document.getElementById('coverage').hidden = false;
    var body = document.getElementById('coverage-body');
    var summary = element('div', { class: 'coverage-summary' });
    summary.appendChild(element('div', { class: 'coverage-figure' }, fixed(coverage.percent, 1) + ' %'));
    summary.appendChild(element('div', {}, 'of the wall seen: ' + thousands(coverage.seen_mm2) + ' of ' +
      thousands(coverage.wall_mm2) + ' mm\u00b2'));
    if (coverage.description) summary.appendChild(element('p', { class: 'note' }, coverage.description));
    body.appendChild(summary);

    var percents = coverage.cumulative_percent || [];
    if (percents.length) body.appendChild(buildCurve(percents));
    if (coverage.overview) {
      var link = element('a', { href: fileUrl(coverage.overview), target: '_blank', rel: 'noopener' });
      var overview = element('img', { id: 'coverage-overview', alt: 'coverage overview' });
      overview.src = fileUrl(coverage.overview);
      link.appendChild(overview);
      body.appendChild(link);
    }
    if ((coverage.patches || []).length) body.appendChild(buildPatches(coverage.patches));
  }

  // Cumulative coverage against frame, as SVG; a click jumps to the frame under the pointer.
  function buildCurve(percents) {
    var ns = 'http://www.w3.org/2000/svg', w = 380, h = 150, left = 34, right = 8, top = 8, bottom = 22;
    var svg = document.createElementNS(ns, 'svg');
    svg.setAttribute('id', 'coverage-curve');
    svg.setAttribute('width', w);
    svg.setAttribute('height', h);
    svg.setAttribute('viewBox', '0 0 ' + w + ' ' + h);
    function add(tag, attributes, text) {
      var node = document.createElementNS(ns, tag);
      Object.keys(attributes).forEach(function (key) { node.setAttribute(key, attributes[key]); });
      if (text !== undefined) node.textContent = text;
      svg.appendChild(node);
      return node;
    }
    var count = percents.length;
    function x(i) { return left + (count > 1 ? i / (count - 1) : 0.5) * (w - left - right); }
    function y(p) { return top + (1 - p / 100) * (h - top - bottom); }
    [0, 50, 100].forEach(function (p) {
      add('line', { x1: left, x2: w - right, y1: y(p), y2: y(p), stroke: '#2a2f37' });
      add('text', { x: left - 4, y: y(p) + 4, 'text-anchor': 'end', fill: '#8b94a1', 'font-size': 10 }, p + '%');
    });
    add('text', { x: (left + w - right) / 2, y: h - 6, 'text-anchor': 'middle', fill: '#8b94a1', 'font-size': 10 },
      'frame (wall seen so far)');
    add('polyline', { points: percents.map(function (p, i) { return x(i) + ',' + y(p); }).join(' '),
      fill: 'none', stroke: '#4fc3f7', 'stroke-width': 2 });
    var marker = add('line', { y1: top, y2: h - bottom, stroke: '#ffd54f', 'stroke-width': 1.5 });
    var dot = add('circle', { r: 3.5, fill: '#ffd54f' });
    svg.addEventListener('click', function (event) {
      var box = svg.getBoundingClientRect();
      var t = (event.clientX - box.left - left) / (box.width - left - right);
      show(Math.round(t * (count - 1)));
    });
    curve = { marker: marker, dot: dot, x: x, y: y, percents: percents };
    return svg;
  }

  // A table cell with a small picture, or empty without one.
  function pictureCell(path, alt) {
    var cell = element('td');
    if (path) {
      var img = element('img', { alt: alt, loading: 'lazy' });
      img.src = fileUrl(path);
      cell.appendChild(img);
    }
    return cell;
  }

  function buildPatches(patches) {
    var table = element('table', { id: 'patches' });
    var head = element('tr');
    ['#', 'area', 'centre (mm)', 'look from (mm)', 'nearest frame', ''].forEach(function (title) {
      head.appendChild(element('th', {}, title));
    });
    table.appendChild(head);
    patches.forEach(function (patch) {
      var tr = element('tr', { class: 'patch', 'data-frame': patch.nearest_frame });
      tr.appendChild(element('td', {}, String(patch.rank)));
      tr.appendChild(element('td', {}, fixed(patch.area_mm2, 1) + ' mm\u00b2'));
      tr.appendChild(element('td', {}, vectorText(patch.centre_mm, 1)));
      tr.appendChild(element('td', { title: 'forward ' + vectorText(patch.pose.forward, 2) + ', up ' + vectorText(patch.pose.up, 2) },
        vectorText(patch.pose.position_mm, 1)));
      var cell = element('td');
      var position = positionOfFrameIndex[patch.nearest_frame];
      if (position !== undefined) {
        var button = element('button', { type: 'button' }, 'frame ' + patch.nearest_frame);
        cell.appendChild(button);
        tr.addEventListener('click', function () { show(position); });
      } else {
        cell.textContent = '\u2013';
      }
      tr.appendChild(cell);
      tr.appendChild(pictureCell(patch.picture, 'unseen patch ' + patch.rank));
      table.appendChild(tr);
    });
    return table;
  }

  function markCoverage() {
    if (curve && current < curve.percents.length) {
      var px = curve.x(current);
      curve.marker.setAttribute('x1', px);
      curve.marker.setAttribute('x2', px);
      curve.dot.setAttribute('cx', px);
      curve.dot.setAttribute('cy', curve.y(curve.percents[current]));
    }
    var index = frames.length ? frames[current].index : -1;
    document.querySelectorAll('#patches tr.patch').forEach(function (tr) {
      tr.classList.toggle('current', Number(tr.getAttribute('data-frame')) === index);
    });
  }

  // ---- polyp candidates: a sortable table, a row shows its frame --------------------------

  function buildCandidates() {
    var candidates = data.candidates || [];
    if (!candidates.length) return;
    document.getElementById('candidates').hidden = false;
    var table = document.getElementById('candidate-table');
    var columns = [
      { title: '#', key: 'rank', text: function (c) { return String(c.rank); } },
      { title: 'diameter', key: 'diameter_mm', text: function (c) { return fixed(c.diameter_mm, 1) + ' mm'; } },
      { title: 'score', key: 'score', text: function (c) { return fixed(c.score, 2); } },
      { title: 'shape index', key: 'shape_index', text: function (c) { return fixed(c.shape_index, 2); } },
      { title: 'centre (mm)', key: null, text: function (c) { return vectorText(c.centre_mm, 1); } },
      { title: 'frame', key: 'frame', text: function (c) { return c.frame >= 0 ? 'frame ' + c.frame : '\u2013'; } }
    ];
    var order = { key: 'rank', descending: false };
    var rows = candidates.map(function (candidate) {
      var tr = element('tr', { class: 'candidate', 'data-frame': candidate.frame, 'data-rank': candidate.rank });
      columns.forEach(function (column) { tr.appendChild(element('td', {}, column.text(candidate))); });
      tr.appendChild(pictureCell(candidate.picture, 'candidate ' + candidate.rank));
      var position = positionOfFrameIndex[candidate.frame];
      if (position !== undefined) tr.addEventListener('click', function () { show(position); });
      return { candidate: candidate, tr: tr };
    });
    var head = element('tr');
    columns.concat([{ title: '', key: null }]).forEach(function (column) {
      var th = element('th', column.key ? { class: 'sortable', 'data-key': column.key } : {}, column.title);
      if (column.key) {
        th.addEventListener('click', function () {
          order = { key: column.key, descending: order.key === column.key ? !order.descending : column.key !== 'rank' };
          fill();
        });
      }
      head.appendChild(th);
    });
    function fill() {
      table.textContent = '';
      table.appendChild(head);
      rows.slice().sort(function (a, b) {
        var difference = a.candidate[order.key] - b.candidate[order.key];
        return (order.descending ? -difference : difference) || a.candidate.rank - b.candidate.rank;
      }).forEach(function (row) { table.appendChild(row.tr); });
      head.querySelectorAll('th.sortable').forEach(function (th) {
        th.setAttribute('aria-sort', th.getAttribute('data-key') !== order.key ? 'none'
          : order.descending ? 'descending' : 'ascending');
      });
    }
    fill();
  }

  function markCandidates() {
    var index = frames.length ? frames[current].index : -1;
    document.querySelectorAll('#candidate-table tr.candidate').forEach(function (tr) {
      tr.classList.toggle('current', Number(tr.getAttribute('data-frame')) === index);
    });
    drawRings();
  }

  // Rings on the large sheet around the current frame's candidates: the sheet holds three crosses
  // (left eye, right eye, anaglyph) with sheet_gap_px between them; a ring's place is given as
  // fractions of one cross. The image is drawn with object-fit: contain, so the picture's own
  // rectangle inside the element is worked out first.
  var ringLayer = null;
  function drawRings() {
    if (!ringLayer) {
      ringLayer = element('div', { id: 'rings' });
      largeLink.appendChild(ringLayer);
    }
    ringLayer.textContent = '';
    if (!frames.length || !large.naturalWidth || !(data.candidates || []).length) return;
    var frame = frames[current];
    if (!frame.sheet) return;
    var naturalW = large.naturalWidth, naturalH = large.naturalHeight;
    var boxW = large.clientWidth, boxH = large.clientHeight;
    var scale = Math.min(boxW / naturalW, boxH / naturalH);
    var offsetX = large.offsetLeft + (boxW - naturalW * scale) / 2, offsetY = large.offsetTop + (boxH - naturalH * scale) / 2;
    var gap = data.sheet_gap_px || 0;
    var crossW = (naturalW - 2 * gap) / 3;
    data.candidates.forEach(function (candidate) {
      if (candidate.frame !== frame.index || !candidate.ring) return;
      [candidate.ring.left, candidate.ring.right, candidate.ring.left].forEach(function (ring, cross) {
        if (!ring) return;
        var x = offsetX + (cross * (crossW + gap) + ring.x * crossW) * scale;
        var y = offsetY + ring.y * naturalH * scale;
        var r = Math.max(6, ring.radius * crossW * scale);
        var circle = element('span', { class: 'ring', title: 'candidate ' + candidate.rank + ': ' +
          fixed(candidate.diameter_mm, 1) + ' mm' });
        circle.style.left = (x - r) + 'px';
        circle.style.top = (y - r) + 'px';
        circle.style.width = circle.style.height = (2 * r) + 'px';
        ringLayer.appendChild(circle);
      });
    });
  }
  large.addEventListener('load', drawRings);
  window.addEventListener('resize', drawRings);

  function buildMeasurements() {
    var rows = data.measurements || [];
    if (!rows.length) return;
    document.getElementById('measurements').hidden = false;
    var table = document.getElementById('measurement-table');
    rows.forEach(function (row) {
      var tr = element('tr');
      tr.appendChild(element('th', {}, row.label));
      tr.appendChild(element('td', {}, row.value));
      table.appendChild(tr);
    });
  }

  // ---- start ------------------------------------------------------------------------------

  if (volume) {
    try {
      decodeVolume();
      buildSlices();
    } catch (error) {
      grey = null;
      report('review_volume.js is broken: ' + error.message);
    }
  }
  if (!grey) document.getElementById('slices-panel').hidden = true;

  buildStrip();
  buildCoverage();
  buildCandidates();
  buildMeasurements();
  large.addEventListener('error', function () { report('cannot load ' + large.getAttribute('src') + '.'); });

  slider.max = String(Math.max(0, frames.length - 1));
  slider.addEventListener('input', function () { show(Number(slider.value)); });
  document.getElementById('previous').addEventListener('click', function () { show(current - 1); });
  document.getElementById('next').addEventListener('click', function () { show(current + 1); });
  document.addEventListener('keydown', function (event) {
    if (event.target === slider || event.altKey || event.ctrlKey || event.metaKey) return;  // the slider steps itself
    var steps = { ArrowLeft: current - 1, ArrowRight: current + 1, Home: 0, End: frames.length - 1 };
    if (!(event.key in steps)) return;
    event.preventDefault();
    show(steps[event.key]);
  });

  var start = /#frame=(\d+)/.exec(location.hash);
  var startPosition = start ? positionOfFrameIndex[Number(start[1])] : undefined;
  if (!frames.length) {
    report('the folder holds no frames.');
    document.getElementById('viewer').hidden = true;
  } else {
    show(startPosition === undefined ? 0 : startPosition);
  }
  document.body.setAttribute('data-ready', '1');
})();

// lucent.js - turns <img data-lucent-*> elements into Lucent renders: sets each one's src to the GET
// /v1/render URL of the lucentd that served this script. No dependencies; served by lucentd at /lucent.js.
//
// Usage (paste into any page; HOST is where lucentd listens, e.g. 127.0.0.1:8080):
//
//   <script src="http://HOST/lucent.js" defer></script>
//   <img data-lucent-mesh="protrusion" data-lucent-preset="skin1" data-lucent-light-dir="-1,0,0"
//        data-lucent-size="256" alt="Skin lit from the side">
//
// Attributes: every data-lucent-NAME becomes the query field NAME of GET /v1/render, dashes turned into
// underscores (the README's "Query fields" table lists them all), checked by the server. The common ones:
//   data-lucent-mesh             sphere | torus | protrusion | bunny, or the 64-hex-digit id of an uploaded mesh
//   data-lucent-preset           apple, chicken1, chicken2, cream, ketchup, marble, potato, skimmilk, skin1,
//                                skin2, spectralon, wholemilk
//   data-lucent-sigma-a, data-lucent-sigma-s-prime   "r,g,b" in mm^-1, instead of a preset
//   data-lucent-eta, data-lucent-scale-mm, data-lucent-g
//   data-lucent-profile          dipole | asymptotic_dipole | better_dipole | burley
//   data-lucent-light-dir        "x,y,z": the way the light travels; data-lucent-light-pos for a point light
//   data-lucent-light-intensity, data-lucent-light-color
//   data-lucent-camera-pos, data-lucent-camera-target, data-lucent-fov
//   data-lucent-method           five | single | auto | reference | path;  data-lucent-samples  1..64
//   data-lucent-path-samples, data-lucent-path-time-s   walks a pixel and a time budget for method path
//   data-lucent-background       "r,g,b,a";  data-lucent-exposure  stops
// and one shorthand:
//   data-lucent-size             N sets both w and h (data-lucent-w / data-lucent-h set them apart)
// Unless given, w and h are the element's width and height attributes, else 256.
//
// The server origin comes from this script's own src, so the images render on the daemon that served it.
// <img> cannot send a bearer token: use a daemon without --token-file for embedded previews. A bad value
// makes the image fail to load (the element gets data-lucent-error); open its src to read the server's
// message. After adding elements later, call window.lucent.apply(); window.lucent.url(img) gives one URL.
(function () {
  'use strict';

  var script = document.currentScript;
  var origin = new URL(script ? script.src : location.href).origin;

  function url(img) {
    var fields = [];
    var w = img.getAttribute('width') || '256';
    var h = img.getAttribute('height') || '256';
    for (var i = 0; i < img.attributes.length; i++) {
      var a = img.attributes[i];
      if (a.name.indexOf('data-lucent-') !== 0 || a.name === 'data-lucent-error') continue;
      var name = a.name.slice('data-lucent-'.length).replace(/-/g, '_');
      if (name === 'size') w = h = a.value;
      else if (name === 'w') w = a.value;
      else if (name === 'h') h = a.value;
      else fields.push([name, a.value]);
    }
    fields.push(['w', w], ['h', h]);
    return origin + '/v1/render?' + fields.map(function (f) {
      return f[0] + '=' + encodeURIComponent(f[1]).replace(/%2C/g, ',');
    }).join('&');
  }

  function apply(root) {
    var images = (root || document).querySelectorAll('img[data-lucent-mesh], img[data-lucent-preset]');
    for (var i = 0; i < images.length; i++) {
      var img = images[i];
      img.removeAttribute('data-lucent-error');
      img.onerror = function () {
        this.setAttribute('data-lucent-error', 'the render failed; open the image URL for the server\'s message');
      };
      img.src = url(img);
    }
  }

  window.lucent = { url: url, apply: apply, origin: origin };
  if (document.readyState === 'loading') document.addEventListener('DOMContentLoaded', function () { apply(); });
  else apply();
})();

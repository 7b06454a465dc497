/* synsculpt's 3-D motion player (three.js, classic script: works from file://).
 *
 *   var player = SynPlayer.create(container, robot, {onFrame: function (frame, time) {}});
 *   player.setMotion(motion);  player.setTime(seconds);  player.setFrame(k);
 *   player.play();  player.pause();  player.setSpeed(x);  player.playing();
 *   player.setHumanOffset(metres);  player.linkPositions();  // link-frame world positions (tests)
 *
 * robot: what tools/report/urdf_fk.py Robot.description() writes: links in tree order, each with its parent
 *   index, joint origin (xyz, quaternion w,x,y,z), axis, type and q index (-1 for fixed); base_q (q indexes of
 *   a free base's quaternion w,x,y,z and translation) or null; feet (link index, sole points in the link frame).
 * motion: frames, nq, time (Float32Array [T], s), q (Float32Array [T*nq]); optional landmarks {names,
 *   positions (Float32Array [T*L*3], NaN = no target)}: the IK targets, drawn where they are; optional human
 *   {names, parents (index or -1), positions (Float32Array [T*N*3])}: the capture, drawn beside the robot;
 *   feet flags contact and sliding (Uint8Array [T*F]).
 *
 * The forward kinematics is the URDF's: parent pose * joint origin * rotation about the axis by q (revolute)
 * or a translation along it (prismatic). Z is up, as in every synsculpt file.
 */
var SynPlayer = (function () {
  'use strict';
  var ROBOT_COLOR = 0x8a9bb0, JOINT_COLOR = 0x4a5668, HUMAN_COLOR = 0xe07a1f, TARGET_COLOR = 0xc2185b;
  var FOOT_COLORS = {free: 0x9aa5b1, contact: 0x2a9d8f, sliding: 0xd62828};
  var BONE_RADIUS = 0.025;

  function create(container, robot, options) {
    options = options || {};
    var width = container.clientWidth || 800, height = container.clientHeight || 480;
    var renderer = new THREE.WebGLRenderer({antialias: true, preserveDrawingBuffer: true});
    renderer.setPixelRatio(window.devicePixelRatio || 1);
    renderer.setSize(width, height);
    container.appendChild(renderer.domElement);
    var scene = new THREE.Scene();
    scene.background = new THREE.Color(0xf4f5f7);
    var camera = new THREE.PerspectiveCamera(40, width / height, 0.05, 100);
    camera.up.set(0, 0, 1);
    scene.add(new THREE.HemisphereLight(0xffffff, 0x667788, 2.0));
    var sun = new THREE.DirectionalLight(0xffffff, 1.5);
    sun.position.set(3, -2, 5);
    scene.add(sun);
    var grid = new THREE.GridHelper(20, 40, 0x99a0aa, 0xcdd2d8);
    grid.rotation.x = Math.PI / 2;  // GridHelper lies in XZ; synsculpt's ground is XY
    scene.add(grid);

    // One bone per link with a parent: a unit cylinder along Y, placed between the two link origins.
    var links = robot.links, n = links.length;
    var boneMaterial = new THREE.MeshStandardMaterial({color: ROBOT_COLOR, roughness: 0.6});
    var jointMaterial = new THREE.MeshStandardMaterial({color: JOINT_COLOR, roughness: 0.6});
    var cylinder = new THREE.CylinderGeometry(BONE_RADIUS, BONE_RADIUS, 1, 12);
    var sphere = new THREE.SphereGeometry(BONE_RADIUS * 1.25, 12, 8);
    var bones = [], joints = [];
    for (var i = 0; i < n; i++) {
      var joint = new THREE.Mesh(sphere, jointMaterial);
      scene.add(joint);
      joints.push(joint);
      if (links[i].parent >= 0) {
        var bone = new THREE.Mesh(cylinder, boneMaterial);
        scene.add(bone);
        bones.push({mesh: bone, link: i});
      }
    }
    // A leaf link whose centre of mass lies away from its joint (the G1's head sits on the torso's frame):
    // a bone to the centre of mass and a ball there, sized by that distance.
    var hasChild = links.map(function () { return false; });
    links.forEach(function (link) { if (link.parent >= 0) hasChild[link.parent] = true; });
    var tips = [];
    links.forEach(function (link, i) {
      var com = new THREE.Vector3(link.com[0], link.com[1], link.com[2]);
      if (hasChild[i] || com.length() < 0.04) return;
      var radius = Math.max(0.03, Math.min(0.09, 0.2 * com.length()));
      var ball = new THREE.Mesh(new THREE.SphereGeometry(radius, 16, 12), boneMaterial);
      var bone = new THREE.Mesh(cylinder, boneMaterial);
      scene.add(ball); scene.add(bone);
      tips.push({link: i, com: com, ball: ball, bone: bone});
    });
    // Feet: a box through the sole points, coloured by contact state.
    var feet = (robot.feet || []).map(function (foot) {
      var box = new THREE.Box3();
      foot.sole_points.forEach(function (p) { box.expandByPoint(new THREE.Vector3(p[0], p[1], p[2])); });
      var size = box.getSize(new THREE.Vector3()), centre = box.getCenter(new THREE.Vector3());
      var thickness = 0.03;
      var mesh = new THREE.Mesh(new THREE.BoxGeometry(size.x + 0.02, size.y + 0.02, thickness),
                                new THREE.MeshStandardMaterial({color: FOOT_COLORS.free}));
      scene.add(mesh);
      return {mesh: mesh, link: foot.link, centre: centre.add(new THREE.Vector3(0, 0, thickness / 2))};
    });
    var targetMaterial = new THREE.MeshStandardMaterial({color: TARGET_COLOR});
    var targetSphere = new THREE.SphereGeometry(0.022, 10, 8);
    var humanMaterial = new THREE.MeshStandardMaterial({color: HUMAN_COLOR});
    var humanSphere = new THREE.SphereGeometry(0.02, 10, 8);
    var humanLine = new THREE.LineBasicMaterial({color: HUMAN_COLOR});
    var targets = [], humanPoints = [], humanLines = null, humanOffset = 1.0;
    // Places mesh m at point i of frame k of a [T*N*3] array (plus dy); hides it where the point is NaN.
    function placePoint(mesh, array, count, k, i, dy) {
      var o = (k * count + i) * 3, x = array[o], y = array[o + 1], z = array[o + 2];
      mesh.visible = isFinite(x) && isFinite(y) && isFinite(z);
      if (mesh.visible) mesh.position.set(x, y + dy, z);
    }

    var positions = [], rotations = [];
    for (i = 0; i < n; i++) { positions.push(new THREE.Vector3()); rotations.push(new THREE.Quaternion()); }
    var origins = links.map(function (link) {
      if (link.parent < 0) return null;
      var q = link.quaternion;
      return {xyz: new THREE.Vector3(link.xyz[0], link.xyz[1], link.xyz[2]),
              rotation: new THREE.Quaternion(q[1], q[2], q[3], q[0]),
              axis: new THREE.Vector3(link.axis[0], link.axis[1], link.axis[2]).normalize()};
    });
    var motion = null, frame = 0, speed = 1, playing = false, playStart = 0, playFrom = 0;
    var target = new THREE.Vector3(0, 0, 0.8), azimuth = -0.9, elevation = 0.22, distance = 3.2;
    var scratch = new THREE.Quaternion(), up = new THREE.Vector3(0, 1, 0), delta = new THREE.Vector3();

    function forwardKinematics(k) {
      var q = motion.q, base = k * motion.nq;
      for (var i = 0; i < n; i++) {
        var link = links[i];
        if (link.parent < 0) {
          if (robot.base_q) {
            var b = robot.base_q;
            rotations[i].set(q[base + b[1]], q[base + b[2]], q[base + b[3]], q[base + b[0]]).normalize();
            positions[i].set(q[base + b[4]], q[base + b[5]], q[base + b[6]]);
          } else {
            rotations[i].identity();
            positions[i].set(0, 0, 0);
          }
          continue;
        }
        var o = origins[i], parent = link.parent;
        positions[i].copy(o.xyz).applyQuaternion(rotations[parent]).add(positions[parent]);
        rotations[i].copy(rotations[parent]).multiply(o.rotation);
        if (link.q >= 0 && (link.type === 'revolute' || link.type === 'continuous')) {
          rotations[i].multiply(scratch.setFromAxisAngle(o.axis, q[base + link.q]));
        } else if (link.q >= 0 && link.type === 'prismatic') {
          positions[i].add(delta.copy(o.axis).applyQuaternion(rotations[i]).multiplyScalar(q[base + link.q]));
        }
      }
    }

    function place() {
      forwardKinematics(frame);
      for (var i = 0; i < n; i++) joints[i].position.copy(positions[i]);
      bones.forEach(function (bone) {
        var from = positions[links[bone.link].parent], to = positions[bone.link];
        delta.subVectors(to, from);
        var length = delta.length();
        bone.mesh.visible = length > 1e-4;
        if (!bone.mesh.visible) return;
        bone.mesh.position.copy(from).addScaledVector(delta, 0.5);
        bone.mesh.quaternion.setFromUnitVectors(up, delta.divideScalar(length));
        bone.mesh.scale.set(1, length, 1);
      });
      tips.forEach(function (tip) {
        var from = positions[tip.link];
        tip.ball.position.copy(tip.com).applyQuaternion(rotations[tip.link]).add(from);
        delta.subVectors(tip.ball.position, from);
        var length = delta.length();
        tip.bone.position.copy(from).addScaledVector(delta, 0.5);
        tip.bone.quaternion.setFromUnitVectors(up, delta.divideScalar(length));
        tip.bone.scale.set(1, length, 1);
      });
      var nf = feet.length;
      feet.forEach(function (foot, f) {
        foot.mesh.quaternion.copy(rotations[foot.link]);
        foot.mesh.position.copy(foot.centre).applyQuaternion(rotations[foot.link]).add(positions[foot.link]);
        var sliding = motion.sliding && motion.sliding[frame * nf + f];
        var contact = motion.contact && motion.contact[frame * nf + f];
        foot.mesh.material.color.setHex(sliding ? FOOT_COLORS.sliding : contact ? FOOT_COLORS.contact : FOOT_COLORS.free);
      });
      if (motion.landmarks) {
        var L = motion.landmarks.names.length;
        for (var l = 0; l < L; l++) placePoint(targets[l], motion.landmarks.positions, L, frame, l, 0);
      }
      if (motion.human) {
        var H = motion.human.names.length, ends = [];
        for (var h = 0; h < H; h++) placePoint(humanPoints[h], motion.human.positions, H, frame, h, humanOffset);
        motion.human.parents.forEach(function (parent, h) {
          if (parent >= 0 && humanPoints[h].visible && humanPoints[parent].visible) {
            ends.push(humanPoints[parent].position.clone(), humanPoints[h].position.clone());
          }
        });
        humanLines.geometry.setFromPoints(ends);
      }
      // The camera follows the pelvis horizontally.
      target.set(positions[0].x, positions[0].y + (motion.human ? humanOffset / 2 : 0), 0.8);
      camera.position.set(target.x + distance * Math.cos(elevation) * Math.cos(azimuth),
                          target.y + distance * Math.cos(elevation) * Math.sin(azimuth),
                          target.z + distance * Math.sin(elevation));
      camera.lookAt(target);
      renderer.render(scene, camera);
      if (options.onFrame) options.onFrame(frame, motion.time[frame]);
    }

    function setFrame(k) {
      if (!motion) return;
      frame = Math.max(0, Math.min(motion.frames - 1, Math.round(k)));
      place();
    }
    function frameAt(seconds) {  // the last frame at or before `seconds`
      var lo = 0, hi = motion.frames - 1;
      while (lo < hi) { var mid = (lo + hi + 1) >> 1; if (motion.time[mid] <= seconds) lo = mid; else hi = mid - 1; }
      return lo;
    }
    function tick(now) {
      if (!playing) return;
      var t = playFrom + (now - playStart) / 1000 * speed, end = motion.time[motion.frames - 1];
      if (t > end) { playFrom = 0; playStart = now; t = 0; }  // loop
      setFrame(frameAt(t));
      requestAnimationFrame(tick);
    }

    // Orbit: drag to turn, wheel to zoom.
    var dragging = null;
    renderer.domElement.addEventListener('pointerdown', function (e) { dragging = {x: e.clientX, y: e.clientY}; });
    window.addEventListener('pointerup', function () { dragging = null; });
    window.addEventListener('pointermove', function (e) {
      if (!dragging) return;
      azimuth -= (e.clientX - dragging.x) * 0.01;
      elevation = Math.max(-0.2, Math.min(1.4, elevation + (e.clientY - dragging.y) * 0.01));
      dragging = {x: e.clientX, y: e.clientY};
      if (motion) place();
    });
    renderer.domElement.addEventListener('wheel', function (e) {
      e.preventDefault();
      distance = Math.max(1, Math.min(20, distance * Math.exp(e.deltaY * 0.001)));
      if (motion) place();
    }, {passive: false});

    return {
      setMotion: function (m) {
        motion = m;
        targets.concat(humanPoints).forEach(function (mesh) { scene.remove(mesh); });
        if (humanLines) scene.remove(humanLines);
        targets = []; humanPoints = []; humanLines = null;
        function points(count, geometry, material) {
          var meshes = [];
          for (var i = 0; i < count; i++) { var mesh = new THREE.Mesh(geometry, material); scene.add(mesh); meshes.push(mesh); }
          return meshes;
        }
        if (m.landmarks) targets = points(m.landmarks.names.length, targetSphere, targetMaterial);
        if (m.human) {
          humanPoints = points(m.human.names.length, humanSphere, humanMaterial);
          humanLines = new THREE.LineSegments(new THREE.BufferGeometry(), humanLine);
          scene.add(humanLines);
        }
        playFrom = 0;
        setFrame(0);
      },
      setFrame: setFrame,
      setTime: function (seconds) { if (motion) setFrame(frameAt(seconds)); },
      play: function () {
        if (!motion || playing) return;
        playing = true;
        playFrom = motion.time[frame];
        playStart = performance.now();
        requestAnimationFrame(tick);
      },
      pause: function () { playing = false; },
      playing: function () { return playing; },
      setSpeed: function (x) { playFrom = motion ? motion.time[frame] : 0; playStart = performance.now(); speed = x; },
      setHumanOffset: function (metres) { humanOffset = metres; if (motion) place(); },
      frame: function () { return frame; },
      frameCount: function () { return motion ? motion.frames : 0; },
      linkPositions: function () { return positions.map(function (p) { return [p.x, p.y, p.z]; }); },
      canvas: renderer.domElement
    };
  }
  return {create: create};
})();

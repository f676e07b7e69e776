// SpyPluginsCheck: checks lasonic's lcm-spy plugins (lcmtypes/spy/, in build/lcmtypes.jar)
// headless, the way lcm-spy 1.3.1 uses them (tests/integration/spy_plugins.sh runs it):
//  1. lcm-spy's discovery: lcm.util.ClassDiscoverer scans the class path and, like lcm-spy's
//     PluginClassVisitor, takes every class that directly implements lcm.spy.SpyPlugin and has a
//     public no-argument constructor. The three lasonic plugins must be among them.
//  2. canHandle: each plugin takes exactly its type's fingerprint (sector_map_t, grid_map_t,
//     line_map_t) and no other lasonic type's; getAction(null, null) names the action (lcm-spy
//     calls it so to build its menu).
//  3. One message of each type: the plugin's action is run on a desktop as lcm-spy does (a
//     ChannelData whose `last` holds the decoded message), the viewer must have taken the
//     message, and its panel is painted into an image: the expected colours must be where the
//     data is (a laser and a sonar sector, an occupied AGM cell, a laser and a sonar line, the
//     red stale flag).
//  4. Bad messages (wrong counts, NaN, a wrong class) are reported in the status line and
//     painting does not throw.
//
//   java -Djava.awt.headless=true -cp lcm.jar:lcmtypes.jar:DIR SpyPluginsCheck [OUTDIR]
// With OUTDIR the painted panels are written there as PNG. Exit 0 pass, 1 fail.
import java.awt.Component;
import java.awt.Container;
import java.awt.Graphics2D;
import java.awt.image.BufferedImage;
import java.io.File;
import java.util.ArrayList;
import java.util.List;
import javax.imageio.ImageIO;
import javax.swing.Action;
import javax.swing.JDesktopPane;
import javax.swing.JInternalFrame;
import javax.swing.SwingUtilities;
import lasonic.grid_map_t;
import lasonic.line_map_t;
import lasonic.line_segment_t;
import lasonic.pose2d_t;
import lasonic.sector_map_t;
import lasonic.spy.GridMapPlugin;
import lasonic.spy.LineMapPlugin;
import lasonic.spy.MapPanel;
import lasonic.spy.MapViewer;
import lasonic.spy.SectorMapPlugin;
import lcm.spy.ChannelData;
import lcm.spy.SpyPlugin;

public class SpyPluginsCheck {
  static int failures = 0;
  static File outdir;

  static void check(boolean ok, String what) {
    System.out.println((ok ? "ok   " : "FAIL ") + what);
    if (!ok) failures++;
  }

  static void layout(Component c) {
    if (c instanceof Container) {
      ((Container) c).doLayout();
      for (Component k : ((Container) c).getComponents()) layout(k);
    }
  }

  static pose2d_t pose(double x, double y, double th) {
    pose2d_t p = new pose2d_t();
    p.x = x;
    p.y = y;
    p.theta = th;
    return p;
  }

  static final int W = 500, H = 400;

  /** Runs the plugin's action on a desktop as lcm-spy does; returns the viewer it opened. */
  static MapViewer open(SpyPlugin plugin, String channel, Object msg) throws Exception {
    final JDesktopPane desktop = new JDesktopPane();
    desktop.setSize(W, H);
    final ChannelData cd = new ChannelData();
    cd.name = channel;
    cd.last = msg;
    final List<MapViewer> out = new ArrayList<>();
    SwingUtilities.invokeAndWait(() -> {
      plugin.getAction(desktop, cd).actionPerformed(null);
      for (JInternalFrame f : desktop.getAllFrames())
        if (f instanceof MapViewer) out.add((MapViewer) f);
    });
    check(out.size() == 1, channel + ": the action opened one viewer on the desktop");
    if (out.isEmpty()) throw new RuntimeException("no viewer");
    MapViewer v = out.get(0);
    check(v.messages() == 1, channel + ": the viewer took lcm-spy's newest message");
    check(v.getWidth() == W && v.getHeight() == H, channel + ": the viewer fills lcm-spy's window (" + v.getWidth() + "x" + v.getHeight() + ")");
    return v;
  }

  static BufferedImage paint(MapPanel panel, String name) throws Exception {
    final BufferedImage img = new BufferedImage(W, H, BufferedImage.TYPE_INT_RGB);
    SwingUtilities.invokeAndWait(() -> {
      panel.setSize(W, H);
      layout(panel);
      Graphics2D g = img.createGraphics();
      panel.paint(g);
      g.dispose();
    });
    if (outdir != null) ImageIO.write(img, "png", new File(outdir, name + ".png"));
    return img;
  }

  static int r(int rgb) { return (rgb >> 16) & 0xff; }
  static int g(int rgb) { return (rgb >> 8) & 0xff; }
  static int b(int rgb) { return rgb & 0xff; }

  interface PixelTest { boolean test(int rgb); }

  static int count(BufferedImage img, PixelTest t) {
    int n = 0;
    for (int y = 0; y < img.getHeight(); y++)
      for (int x = 0; x < img.getWidth(); x++)
        if (t.test(img.getRGB(x, y))) n++;
    return n;
  }

  /** Whether a pixel within 2 px of (x, y) passes t (lines are anti-aliased at their edges). */
  static boolean near(BufferedImage img, int[] p, PixelTest t) {
    for (int dy = -2; dy <= 2; dy++)
      for (int dx = -2; dx <= 2; dx++)
        if (t.test(img.getRGB(p[0] + dx, p[1] + dy))) return true;
    return false;
  }

  /** Screen pixel of world point (x, y) in a panel of scale 55 px/m centred on (cx, cy). */
  static int[] px(double x, double y, double cx, double cy, double scale) {
    return new int[] {(int) Math.round(W / 2.0 + (x - cx) * scale), (int) Math.round(H / 2.0 - (y - cy) * scale)};
  }

  @SuppressWarnings({"unchecked", "rawtypes"})
  public static void main(String[] args) throws Exception {
    if (args.length > 0) {
      outdir = new File(args[0]);
      outdir.mkdirs();
    }
    // ---- 1. discovery, as lcm-spy does it
    final List<String> found = new ArrayList<>();
    lcm.util.ClassDiscoverer.findClasses((String name, Class cls) -> {
      for (Class<?> i : cls.getInterfaces())
        if (i.equals(SpyPlugin.class)) {
          try {
            cls.getConstructor().newInstance();
            found.add(cls.getName());
          } catch (Exception e) {
            System.out.println("plugin " + cls.getName() + " cannot be made: " + e);
          }
        }
    });
    for (String n : new String[] {"lasonic.spy.SectorMapPlugin", "lasonic.spy.GridMapPlugin", "lasonic.spy.LineMapPlugin"})
      check(found.contains(n), "lcm-spy's class-path scan finds " + n);

    // ---- 2. canHandle and the action's name
    SpyPlugin sector = new SectorMapPlugin(), grid = new GridMapPlugin(), lines = new LineMapPlugin();
    long[] fps = {sector_map_t.LCM_FINGERPRINT, grid_map_t.LCM_FINGERPRINT, line_map_t.LCM_FINGERPRINT,
                  lasonic.sonar_ring_t.LCM_FINGERPRINT, lasonic.complement_t.LCM_FINGERPRINT};
    SpyPlugin[] plugins = {sector, grid, lines};
    for (int p = 0; p < plugins.length; p++)
      for (int f = 0; f < fps.length; f++)
        check(plugins[p].canHandle(fps[f]) == (p == f),
              plugins[p].getClass().getSimpleName() + (p == f ? " handles " : " ignores ") + "fingerprint " + f);
    for (SpyPlugin p : plugins) {
      Action a = p.getAction(null, null);
      check(a != null && a.getValue(Action.NAME) instanceof String, p.getClass().getSimpleName() + ": getAction(null, null) names the action");
    }

    // ---- 3a. SECTOR_MAP: straight ahead (sector 24) laser, left (sector 36) sonar, its
    // neighbour copied; the sonar stale.
    sector_map_t sm = new sector_map_t();
    sm.utime = 1000000;
    sm.robot_pose = pose(2, 3, 0.7);
    sm.robot_radius = 0.35f;
    sm.max_range = 3.0f;
    sm.nsectors = 48;
    sm.distance = new float[48];
    sm.source = new byte[48];
    sm.laser_distance = new float[48];
    sm.sonar_distance = new float[48];
    java.util.Arrays.fill(sm.distance, -1f);
    for (int k = 22; k <= 26; k++) { sm.distance[k] = 1.0f; sm.source[k] = sector_map_t.SOURCE_LASER; }
    for (int k = 35; k <= 37; k++) { sm.distance[k] = 0.8f; sm.source[k] = sector_map_t.SOURCE_SONAR; }
    sm.distance[38] = 0.8f;
    sm.source[38] = sector_map_t.SOURCE_SONAR_COPIED;
    sm.sonar_stale = 1;
    sm.sonar_age_s = 0.9f;
    sm.laser_age_s = 0.1f;
    MapViewer sv = open(sector, "SECTOR_MAP", sm);
    BufferedImage si = paint(sv.panel(), "sector_map");
    check(sv.panel().status().startsWith("48 sectors: 5 laser, 3 sonar, 1 copied"), "SECTOR_MAP status: " + sv.panel().status());
    // Robot frame, ahead up, 80 px/m: 0.35 + 0.5 m ahead is 68 px above the centre.
    int ahead = si.getRGB(W / 2, H / 2 - 68);
    check(b(ahead) > r(ahead) + 50, "SECTOR_MAP: laser blue straight ahead (" + Integer.toHexString(ahead) + ")");
    int left = si.getRGB(W / 2 - 64, H / 2);
    check(r(left) > b(left) + 100, "SECTOR_MAP: sonar orange on the left (" + Integer.toHexString(left) + ")");
    int behind = si.getRGB(W / 2, H / 2 + 68);
    check(behind == 0xffffffff || (r(behind) > 220 && g(behind) > 220), "SECTOR_MAP: nothing reported behind");
    check(count(si, c -> r(c) > 180 && g(c) < 60 && b(c) < 60) > 20, "SECTOR_MAP: the red stale flag is drawn");

    // ---- 3b. AGM_OPERATIONAL: a 3 x 3 occupied block 1 m east of the robot, light weights west.
    grid_map_t gm = new grid_map_t();
    gm.utime = 1000000;
    gm.robot_pose = pose(5.05, 5.05, 0);
    gm.origin_x = 0;
    gm.origin_y = 0;
    gm.cell_size = 0.1f;
    gm.width = 100;
    gm.height = 100;
    gm.gp_threshold = 2;
    gm.ncells = 10000;
    gm.g = new short[10000];
    gm.h = new short[10000];
    gm.gp = new int[10000];
    gm.heard = new byte[10000];
    for (int iy = 49; iy <= 51; iy++)
      for (int ix = 59; ix <= 61; ix++) { gm.g[iy * 100 + ix] = 3; gm.gp[iy * 100 + ix] = 9; }
    gm.g[50 * 100 + 35] = 1;
    gm.gp[50 * 100 + 35] = 1;
    // A second block 1 m south that only echoes the laser could not check made.
    for (int iy = 39; iy <= 41; iy++)
      for (int ix = 49; ix <= 51; ix++) { gm.g[iy * 100 + ix] = 3; gm.gp[iy * 100 + ix] = 9; gm.heard[iy * 100 + ix] = grid_map_t.HEARD_UNCHECKED; }
    MapViewer gv = open(grid, "AGM_OPERATIONAL", gm);
    BufferedImage gi = paint(gv.panel(), "agm_operational");
    check(gv.panel().status().contains("18 occupied (Gp >= 2), 1 more with G > 0; 9 of them only echoes the laser could not check made"),
          "AGM status: " + gv.panel().status());
    int[] un = px(5.05, 4.05, 5.05, 5.05, 55);
    int uc = gi.getRGB(un[0], un[1]);
    check(r(uc) == 120 && g(uc) == 110 && b(uc) == 160, "AGM: the unchecked cell has its own colour (" + Integer.toHexString(uc) + ")");
    int[] occ = px(6.05, 5.05, 5.05, 5.05, 55);
    int oc = gi.getRGB(occ[0], occ[1]);
    check(r(oc) == 140 && g(oc) == 56 && b(oc) == 0, "AGM: the occupied cell is dark where it is (" + Integer.toHexString(oc) + ")");
    int[] wk = px(3.55, 5.05, 5.05, 5.05, 55);
    int wc = gi.getRGB(wk[0], wk[1]);
    check(r(wc) > 240 && g(wc) > 150 && g(wc) < 235 && b(wc) < 200, "AGM: the weighted cell is light orange (" + Integer.toHexString(wc) + ")");
    int[] free = px(5.05, 6.05, 5.05, 5.05, 55);
    check((gi.getRGB(free[0], free[1]) & 0xffffff) != 0x8c3800, "AGM: no occupied colour where the map is empty");

    // ---- 3c. CURRENT_SENSOR_MAP: a laser wall south, a sonar line (glass) north.
    line_map_t lm = new line_map_t();
    lm.utime = 1000000;
    lm.robot_pose = pose(0, 0, 0);
    lm.nsegments = 2;
    lm.segments = new line_segment_t[2];
    lm.segments[0] = new line_segment_t();
    lm.segments[0].x0 = -2; lm.segments[0].y0 = -1.5; lm.segments[0].x1 = 2; lm.segments[0].y1 = -1.5;
    lm.segments[0].source = line_segment_t.SOURCE_LASER;
    lm.segments[1] = new line_segment_t();
    lm.segments[1].x0 = -1; lm.segments[1].y0 = 1.5; lm.segments[1].x1 = 1; lm.segments[1].y1 = 1.5;
    lm.segments[1].source = line_segment_t.SOURCE_SONAR;
    MapViewer lv = open(lines, "CURRENT_SENSOR_MAP", lm);
    BufferedImage li = paint(lv.panel(), "current_sensor_map");
    check(lv.panel().status().equals("1 laser + 1 sonar lines"), "CSM status: " + lv.panel().status());
    check(near(li, px(1.0, -1.5, 0, 0, 55), c -> b(c) > 150 && r(c) < 60), "CSM: the laser line is blue where it is");
    check(near(li, px(0.5, 1.5, 0, 0, 55), c -> r(c) > 190 && b(c) < 40), "CSM: the sonar line is orange where it is");
    check(!near(li, px(0.5, 0.5, 0, 0, 55), c -> r(c) > 190 && b(c) < 40), "CSM: no line where there is none");

    // ---- 4. bad messages
    sm.nsectors = 60;  // arrays hold 48
    SectorMapPlugin.Panel sp2 = new SectorMapPlugin.Panel();
    sp2.setMessage(sm);
    paint(sp2, "bad_sector");
    check(sp2.status().startsWith("invalid sector_map_t"), "bad SECTOR_MAP: " + sp2.status());
    gm.width = 7;
    GridMapPlugin.Panel gp2 = new GridMapPlugin.Panel();
    gp2.setMessage(gm);
    paint(gp2, "bad_grid");
    check(gp2.status().equals("invalid grid_map_t: ncells 10000 != width*height"), "bad AGM: " + gp2.status());
    lm.segments[0].x0 = Double.NaN;
    lm.segments[1].source = 42;
    LineMapPlugin.Panel lp2 = new LineMapPlugin.Panel();
    lp2.setMessage(lm);
    paint(lp2, "bad_lines");
    check(lp2.status().equals("0 laser + 0 sonar lines, 2 invalid skipped"), "bad CSM: " + lp2.status());
    lp2.setMessage("a string");
    paint(lp2, "wrong_class");
    check(lp2.status().startsWith("not a line_map_t"), "wrong class: " + lp2.status());

    System.out.println(failures == 0 ? "SpyPluginsCheck: PASS" : "SpyPluginsCheck: " + failures + " FAILED");
    System.exit(failures == 0 ? 0 : 1);
  }
}
